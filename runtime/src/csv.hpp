// CSV output (DESIGN §9): header `t,<outputs>`, one row per communication point.
#pragma once

#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace mbgrt::detail {

/// The destination of --out: a file we own, or stdout.
class OutputFile {
 public:
  /// Empty path or "-" means stdout. Throws std::runtime_error if it cannot be opened.
  explicit OutputFile(const std::string& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::FILE* get() const { return f_; }
  const std::string& display_name() const { return name_; }
  /// Writes and flushes at once, so the text survives a later crash.
  /// Throws std::runtime_error on a write error (e.g. disk full).
  void write(std::string_view text);

 private:
  std::FILE* f_;
  bool owned_;
  std::string name_;
};

class CsvWriter {
 public:
  explicit CsvWriter(OutputFile& out) : out_(out) {}

  void header(std::string_view first, std::span<const std::string> names);
  /// Values use the shortest text that reads back as the same double.
  void row(double t, std::span<const double> values);
  long rows() const { return rows_; }

 private:
  OutputFile& out_;
  std::string line_;
  long rows_ = 0;
};

}  // namespace mbgrt::detail
