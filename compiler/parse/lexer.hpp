// parse/lexer.hpp — tokens of the .mbg language (used only by the parser).
#pragma once

#include <string>
#include <vector>

#include "ir/diagnostics.hpp"

namespace mbgc::parse {

enum class Tok {
  Ident, Number, String,
  LParen, RParen, LBracket, RBracket, LBrace, RBrace,
  Comma, Semi, Colon, Dot, DotDot, Assign, Plus, Minus, Star, Slash, Caret, Arrow,
  End, Bad,
};

struct Token {
  Tok kind = Tok::End;
  std::string text;    // identifier, string contents or number spelling
  double number = 0;
  ir::SourceLoc loc;
};

/// Whole-file tokenisation; comments (`//`, `#`, `/* */`) and whitespace are dropped.
/// Lexical errors are reported and produce a Tok::Bad token.
std::vector<Token> lex(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags);

const char* tok_name(Tok t);

}  // namespace mbgc::parse
