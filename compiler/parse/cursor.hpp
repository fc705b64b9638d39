// parse/cursor.hpp — the parser's token stream: looking ahead, consuming,
// reporting, and telling where a statement starts (used only by the parser).
#pragma once

#include <cstddef>
#include <fmt/format.h>
#include <utility>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"
#include "parse/lexer.hpp"

namespace mbgc::parse {

/// Thrown after an error has been reported; the statement parser recovers.
struct ParseError {};

/// A name as written, with its interpolations (`link{i-1}`), and its span.
struct Name {
  std::string text;
  ir::SourceLoc loc;
};

class Cursor {
 public:
  Cursor(std::vector<Token> toks, ir::Diagnostics& diags) : toks_(std::move(toks)), diags_(diags) {}

 protected:
  const Token& peek(std::size_t k = 0) const {
    std::size_t j = std::min(pos_ + k, toks_.size() - 1);
    return toks_[j];
  }
  bool at(Tok k) const { return peek().kind == k; }
  bool at_ident(const char* text) const { return at(Tok::Ident) && peek().text == text; }
  const Token& next() {
    const Token& t = toks_[pos_];
    if (pos_ + 1 < toks_.size()) ++pos_;
    return t;
  }
  bool accept(Tok k) {
    if (!at(k)) return false;
    next();
    return true;
  }
  [[noreturn]] void fail(const std::string& message, const std::string& hint) {
    diags_.error(peek().loc, message, hint);
    throw ParseError{};
  }
  const Token& expect(Tok k, const char* what_for, const std::string& hint = {}) {
    if (!at(k))
      fail(fmt::format("expected {} {}, found {}", tok_name(k), what_for, describe(peek())), hint);
    return next();
  }
  static std::string describe(const Token& t) {
    if (t.kind == Tok::Ident) return fmt::format("`{}`", t.text);
    if (t.kind == Tok::Number) return fmt::format("number `{}`", t.text);
    return tok_name(t.kind);
  }
  /// A statement starts here: at the start of a line (or after `;`, `{`, `}`),
  /// a keyword or element kind in its shape, or a junction `0 name` / `1 name`.
  bool at_statement_start() const;
  /// Whether the identifier at peek(k) is a keyword or element kind that can
  /// start a statement here (wherever the line starts).
  bool statement_word(std::size_t k = 0) const;
  /// A statement clearly begins at the start of this line: a keyword or element
  /// kind followed by a name (`R load`, `param k`), or a multibody keyword in
  /// its shape. Used to tell an unfinished expression or block from the next statement.
  bool new_statement_here() const;
  /// `b` starts right where `a` ends: no whitespace between them.
  static bool adjacent(const Token& a, const Token& b) {
    return a.loc.line == b.loc.line && a.loc.col + a.loc.length == b.loc.col;
  }
  /// Extends `loc` to the end of `last` (a span stays on one line).
  static void extend(ir::SourceLoc& loc, const ir::SourceLoc& last) {
    if (last.line == loc.line) loc.length = last.col + last.length - loc.col;
  }


  std::vector<Token> toks_;
  std::size_t pos_ = 0;
  ir::Diagnostics& diags_;
};

}  // namespace mbgc::parse
