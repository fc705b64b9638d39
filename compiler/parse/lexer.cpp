#include "parse/lexer.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>

namespace mbgc::parse {

const char* tok_name(Tok t) {
  switch (t) {
    case Tok::Ident: return "a name";
    case Tok::Number: return "a number";
    case Tok::String: return "a string";
    case Tok::LParen: return "`(`";
    case Tok::RParen: return "`)`";
    case Tok::LBracket: return "`[`";
    case Tok::RBracket: return "`]`";
    case Tok::LBrace: return "`{`";
    case Tok::RBrace: return "`}`";
    case Tok::Comma: return "`,`";
    case Tok::Semi: return "`;`";
    case Tok::Colon: return "`:`";
    case Tok::Dot: return "`.`";
    case Tok::DotDot: return "`..`";
    case Tok::Assign: return "`=`";
    case Tok::Plus: return "`+`";
    case Tok::Minus: return "`-`";
    case Tok::Star: return "`*`";
    case Tok::Slash: return "`/`";
    case Tok::Caret: return "`^`";
    case Tok::Arrow: return "`->`";
    case Tok::End: return "end of file";
    case Tok::Bad: return "an invalid character";
  }
  return "?";
}

std::vector<Token> lex(const ir::SourceManager& sources, int file_id, ir::Diagnostics& diags) {
  const std::string& s = sources.file(file_id).text;
  std::vector<Token> out;
  std::size_t i = 0;
  int line = 1;
  std::size_t line_start = 0;
  auto loc_at = [&](std::size_t pos, std::size_t len) {
    return ir::SourceLoc{file_id, line, static_cast<int>(pos - line_start) + 1,
                         static_cast<int>(len == 0 ? 1 : len)};
  };
  auto newline = [&](std::size_t pos) { ++line; line_start = pos + 1; };

  while (i < s.size()) {
    char c = s[i];
    if (c == '\n') { newline(i); ++i; continue; }
    if (std::isspace(static_cast<unsigned char>(c))) { ++i; continue; }
    if (c == '#' || (c == '/' && i + 1 < s.size() && s[i + 1] == '/')) {
      while (i < s.size() && s[i] != '\n') ++i;
      continue;
    }
    if (c == '/' && i + 1 < s.size() && s[i + 1] == '*') {
      ir::SourceLoc start = loc_at(i, 2);
      i += 2;
      while (i + 1 < s.size() && !(s[i] == '*' && s[i + 1] == '/')) {
        if (s[i] == '\n') newline(i);
        ++i;
      }
      if (i + 1 >= s.size()) {
        diags.error(start, "unterminated comment", "close it with `*/`");
        i = s.size();
        break;
      }
      i += 2;
      continue;
    }
    Token t;
    std::size_t start = i;
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_')) ++i;
      t.kind = Tok::Ident;
      t.text = s.substr(start, i - start);
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      // A `.` followed by another `.` is the range operator: `1..N` is 1 .. N.
      auto range_at = [&](std::size_t j) { return j + 1 < s.size() && s[j] == '.' && s[j + 1] == '.'; };
      while (i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || (s[i] == '.' && !range_at(i)))) ++i;
      if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        std::size_t j = i + 1;
        if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
        if (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) {
          i = j;
          while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
        }
      }
      t.kind = Tok::Number;
      t.text = s.substr(start, i - start);
      char* end = nullptr;
      t.number = std::strtod(t.text.c_str(), &end);
      if (end != t.text.c_str() + t.text.size()) {
        diags.error(loc_at(start, i - start), fmt::format("malformed number `{}`", t.text),
                    "write numbers like 12, 0.4 or 6.5e-3");
        t.kind = Tok::Bad;
      } else if (!std::isfinite(t.number)) {
        diags.error(loc_at(start, i - start), fmt::format("number `{}` is too large for a double", t.text),
                    "the largest finite double is about 1.8e308; give the value in other units, or check the exponent");
        t.kind = Tok::Bad;
      } else if (t.number == 0 && t.text.find_first_of("123456789") < t.text.find_first_of("eE")) {
        diags.error(loc_at(start, i - start), fmt::format("number `{}` is too small for a double: it would be 0", t.text),
                    "the smallest positive double is about 4.9e-324; write 0 if zero is meant, or check the exponent");
        t.kind = Tok::Bad;
      }
    } else if (c == '"') {
      ++i;
      while (i < s.size() && s[i] != '"' && s[i] != '\n') ++i;
      if (i >= s.size() || s[i] != '"') {
        diags.error(loc_at(start, i - start), "unterminated string", "close it with `\"` on the same line");
        t.kind = Tok::Bad;
      } else {
        t.kind = Tok::String;
        t.text = s.substr(start + 1, i - start - 1);
        ++i;
      }
    } else {
      ++i;
      switch (c) {
        case '(': t.kind = Tok::LParen; break;
        case ')': t.kind = Tok::RParen; break;
        case '[': t.kind = Tok::LBracket; break;
        case ']': t.kind = Tok::RBracket; break;
        case '{': t.kind = Tok::LBrace; break;
        case '}': t.kind = Tok::RBrace; break;
        case ',': t.kind = Tok::Comma; break;
        case ';': t.kind = Tok::Semi; break;
        case ':': t.kind = Tok::Colon; break;
        case '.':
          if (i < s.size() && s[i] == '.') { ++i; t.kind = Tok::DotDot; }
          else t.kind = Tok::Dot;
          break;
        case '=': t.kind = Tok::Assign; break;
        case '+': t.kind = Tok::Plus; break;
        case '*': t.kind = Tok::Star; break;
        case '/': t.kind = Tok::Slash; break;
        case '^': t.kind = Tok::Caret; break;
        case '-':
          if (i < s.size() && s[i] == '>') { ++i; t.kind = Tok::Arrow; }
          else t.kind = Tok::Minus;
          break;
        default: {
          t.kind = Tok::Bad;
          std::string shown = (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) >= 127)
                                  ? fmt::format("\\x{:02x}", static_cast<unsigned char>(c))
                                  : std::string(1, c);
          diags.error(loc_at(start, 1), fmt::format("unexpected character `{}`", shown),
                      "names are letters, digits and `_`; operators are + - * / ^");
        }
      }
      t.text = s.substr(start, i - start);
    }
    t.loc = loc_at(start, i - start);
    if (t.kind != Tok::Bad) out.push_back(std::move(t));
  }
  Token end;
  end.kind = Tok::End;
  end.loc = loc_at(i, 1);
  out.push_back(end);
  return out;
}

}  // namespace mbgc::parse
