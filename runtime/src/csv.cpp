#include "csv.hpp"

#include "progress.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <iterator>
#include <stdexcept>

namespace mbgrt::detail {

OutputFile::OutputFile(const std::string& path, Rows rows)
    : f_(stdout), owned_(false), name_(path.empty() || path == "-" ? "<stdout>" : path) {
  if (!(path.empty() || path == "-")) {
    f_ = std::fopen(path.c_str(), "w");
    if (!f_)
      throw std::runtime_error(fmt::format("cannot open output file '{}': {}", path, std::strerror(errno)));
    owned_ = true;
  } else if (is_terminal(stdout)) {
    return;  // a terminal shows rows as they come; nothing there outlives the run
  }
  if (rows != Rows::Whole) return;
  try {
    writer_.emplace(::fileno(f_), name_);
  } catch (const std::runtime_error&) {
    if (owned_) std::fclose(f_);  // the destructor does not run for a constructor that throws
    throw;
  }
  if (owned_) std::fclose(f_);  // the writer has the file now
  f_ = nullptr;
}

OutputFile::~OutputFile() {
  try {
    close();
  } catch (const std::runtime_error&) {
    // an error written out already, or one nobody asked about
  }
}

void OutputFile::write(std::string_view text) {
  if (writer_) {
    writer_->write(text);
    return;
  }
  if (!f_) throw std::runtime_error(fmt::format("writing to {} after it was closed", name_));
  if (std::fwrite(text.data(), 1, text.size(), f_) != text.size() || std::fflush(f_) != 0)
    throw std::runtime_error(fmt::format("writing to {} failed: {}", name_, std::strerror(errno)));
}

void OutputFile::close() {
  if (writer_) writer_->finish();  // the writer writes what is left and ends
  if (!f_) return;
  if (owned_)
    std::fclose(f_);
  else
    std::fflush(f_);
  f_ = nullptr;
}

void CsvWriter::header(std::string_view first, std::span<const std::string> names) {
  line_.assign(first);
  for (const std::string& n : names) {
    line_ += ',';
    line_ += n;
  }
  line_ += '\n';
  out_.write(line_);
}

void CsvWriter::row(double t, std::span<const double> values) {
  // Each value's shortest round-trip text (at most 24 characters: sign,
  // 17 digits, point, exponent) into a buffer sized once, the format
  // compiled: a row of 13 values costs a third of what formatting through a
  // parsed format string and a growing std::string did.
  constexpr std::size_t kWidest = 32;
  line_.resize(kWidest * (values.size() + 1) + 1);
  char* p = fmt::format_to(line_.data(), FMT_COMPILE("{}"), t);
  for (double v : values) {
    *p++ = ',';
    p = fmt::format_to(p, FMT_COMPILE("{}"), v);
  }
  *p++ = '\n';
  out_.write(std::string_view(line_.data(), static_cast<std::size_t>(p - line_.data())));
  ++rows_;
}

}  // namespace mbgrt::detail
