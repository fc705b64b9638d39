#include "csv.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <iterator>
#include <stdexcept>

namespace mbgrt::detail {

OutputFile::OutputFile(const std::string& path)
    : f_(stdout), owned_(false), name_(path.empty() || path == "-" ? "<stdout>" : path) {
  if (path.empty() || path == "-") return;
  f_ = std::fopen(path.c_str(), "w");
  if (!f_)
    throw std::runtime_error(
        fmt::format("cannot open output file '{}': {}", path, std::strerror(errno)));
  owned_ = true;
}

OutputFile::~OutputFile() {
  if (owned_)
    std::fclose(f_);
  else
    std::fflush(f_);
}

void OutputFile::write(std::string_view text) {
  if (std::fwrite(text.data(), 1, text.size(), f_) != text.size() || std::fflush(f_) != 0)
    throw std::runtime_error(fmt::format("writing to {} failed: {}", name_, std::strerror(errno)));
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
  line_.clear();
  fmt::format_to(std::back_inserter(line_), "{}", t);
  for (double v : values) fmt::format_to(std::back_inserter(line_), ",{}", v);
  line_ += '\n';
  out_.write(line_);
  ++rows_;
}

}  // namespace mbgrt::detail
