#include "messages.hpp"

#include <fmt/format.h>

namespace mbgrt::detail {

namespace {
thread_local std::FILE* error_stream = nullptr;  // ErrorRedirect's target, if any
}  // namespace

ErrorRedirect::ErrorRedirect(std::FILE* to) : previous_(error_stream) { error_stream = to; }
ErrorRedirect::~ErrorRedirect() { error_stream = previous_; }

namespace {
void print_diagnostic(const char* severity, const std::string& message) {
  if (error_stream) {
    fmt::print(error_stream, "mbgrt: {}: {}\n", severity, message);
    return;
  }
  std::fflush(stdout);
  fmt::print(stderr, "mbgrt: {}: {}\n", severity, message);
}
}  // namespace

void print_error(const std::string& message) { print_diagnostic("error", message); }
void print_warning(const std::string& message) { print_diagnostic("warning", message); }
void print_note(const std::string& message) { print_diagnostic("note", message); }

}  // namespace mbgrt::detail
