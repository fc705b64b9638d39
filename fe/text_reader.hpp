// fe/text_reader.hpp — line-by-line reading of a plain-text input file with
// each word's line and column, so that an error points at it like an error in
// a model (file:line:col, the line, a caret, a hint).
//
// Shared by the Matrix Market and node-file readers of mbgc-reduce.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ir/diagnostics.hpp"

namespace mbgc::fe {

struct Word {
  std::string_view text;
  ir::SourceLoc loc;
};

/// Reads `path` into `sources` (for the diagnostics) and splits each line
/// into words; `comment` starts a comment that runs to the end of the line.
/// Returns nullopt (with an error) when the file cannot be read.
class TextReader {
 public:
  TextReader(ir::SourceManager& sources, ir::Diagnostics& diags) : sources_(sources), diags_(diags) {}
  bool open(const std::string& path, char comment);

  /// The next line that has a word; false at the end of the file.
  bool next_line(std::vector<Word>& words);
  /// Moves to the next line, whatever it holds; false at the end of the file.
  bool raw_line();
  /// The whole text of the current line (for a header that is itself a comment).
  std::string_view line_text() const { return line_; }
  int line_number() const { return line_no_; }
  ir::SourceLoc line_loc() const { return {file_, line_no_, 1, static_cast<int>(std::max<std::size_t>(line_.size(), 1))}; }
  ir::SourceLoc end_loc() const { return {file_, std::max(line_no_, 1), 1, 1}; }

  /// A word as a finite double / as an integer in [lowest, highest]; an error otherwise.
  std::optional<double> number(const Word& w, const char* what);
  std::optional<long long> integer(const Word& w, const char* what, long long lowest, long long highest);

  ir::Diagnostics& diags() { return diags_; }
  int file() const { return file_; }

 private:
  ir::SourceManager& sources_;
  ir::Diagnostics& diags_;
  int file_ = -1;
  std::string_view text_;
  std::size_t pos_ = 0;
  std::string_view line_;
  int line_no_ = 0;
  char comment_ = '#';
};

}  // namespace mbgc::fe
