// The runtime's messages: "mbgrt: error: ..." and its kin on stderr, or where
// an ErrorRedirect sends them (a sweep case's report, an FMU's logger).
#pragma once

#include <cstdio>
#include <string>

namespace mbgrt::detail {

/// Prints "mbgrt: error: <message>" on stderr, or on the stream an
/// ErrorRedirect of this thread names.
void print_error(const std::string& message);
/// "mbgrt: warning: ..." where print_error writes.
void print_warning(const std::string& message);
/// "mbgrt: note: ..." where print_error writes.
void print_note(const std::string& message);

/// While alive, print_error on this thread writes to `to` (a sweep case's report).
class ErrorRedirect {
 public:
  explicit ErrorRedirect(std::FILE* to);
  ~ErrorRedirect();
  ErrorRedirect(const ErrorRedirect&) = delete;
  ErrorRedirect& operator=(const ErrorRedirect&) = delete;

 private:
  std::FILE* previous_;
};

}  // namespace mbgrt::detail
