// CSV output (docs/cli.md): header `t,<outputs>`, one row per communication point.
#pragma once

#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "row_writer.hpp"

namespace mbgrt::detail {

/// The destination of --out: a file we own, or stdout.
class OutputFile {
 public:
  /// How much of a write survives the simulator's death.
  enum class Rows {
    AsWritten,  ///< written and flushed at once: a crash keeps what was written, a SIGKILL may tear a row
    Whole,      ///< through a writer process that writes whole lines only (see below)
  };
  /// Empty path or "-" means stdout. Throws std::runtime_error if it cannot be opened.
  ///
  /// Rows::Whole forks a writer process that owns the destination
  /// (row_writer.hpp): this process copies the text into memory the two
  /// share, with no syscall, and the writer writes it out every few
  /// milliseconds, only up to the last newline. A simulator killed by SIGKILL
  /// (kill -9, the out-of-memory killer) leaves a file of whole rows holding
  /// every row it finished: its socket to the writer closes, and the writer
  /// writes what the memory holds and drops the unfinished row. The writer
  /// ignores SIGINT, SIGTERM and SIGHUP (the simulator ends after a whole row
  /// on those) and is waited for in close(). Only for a process with one
  /// thread (a single run: not a sweep, not under MPI).
  OutputFile(const std::string& path, Rows rows = Rows::AsWritten);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& display_name() const { return name_; }
  /// Writes and flushes at once (Rows::Whole: hands the text to the writer),
  /// so the text survives a later crash. Throws std::runtime_error on a write
  /// error (e.g. disk full; Rows::Whole: at the first write after the writer
  /// met it, or in close()).
  void write(std::string_view text);
  /// Ends the output: with a writer process, waits until it has written
  /// everything. Throws std::runtime_error if it could not. Idempotent; the
  /// destructor calls it and swallows the error.
  void close();

 private:
  std::FILE* f_;
  bool owned_;
  std::string name_;
  std::optional<RowWriter> writer_;  ///< Rows::Whole: the writer process, which has the file
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
