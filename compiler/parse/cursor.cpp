#include "parse/cursor.hpp"

#include <map>
#include <set>

#include "parse/parse.hpp"

namespace mbgc::parse {
namespace {

const std::set<std::string> kElementKinds = {"Se", "Sf", "I", "C", "R", "TF", "GY", "MTF", "MGY", "CN"};
const std::set<std::string> kKeywords = {"model", "import", "param", "signal", "output", "bond",
                                         "simulate", "component", "instance", "body", "ground",
                                         "joint", "force", "contact", "tyre", "gravity", "constraints", "for", "scene"};
/// The multibody keywords are also ordinary names in bond-graph models
/// (`I body = m`, `Se gravity = ...`), so they start a statement only in their
/// statement's shape: followed, on the same line, by this token.
const std::map<std::string, Tok> kShapedKeywords = {
    {"body", Tok::Ident},    {"joint", Tok::Ident},   {"for", Tok::Ident},     {"force", Tok::Ident},
    {"contact", Tok::Ident}, {"tyre", Tok::Ident},
    {"ground", Tok::LBrace}, {"gravity", Tok::Assign}, {"constraints", Tok::Assign}, {"scene", Tok::Ident}};

}  // namespace

const std::set<std::string>& statement_keywords() { return kKeywords; }
const std::set<std::string>& element_kinds() { return kElementKinds; }

bool Cursor::at_statement_start() const {
  if (at(Tok::End) || at(Tok::RBrace)) return true;
  // A statement starts a line (or follows `;`): a 0 or 1 inside an
  // expression, or a parameter named like an element kind, does not.
  bool line_start = pos_ == 0 || toks_[pos_ - 1].loc.line != peek().loc.line ||
                    toks_[pos_ - 1].kind == Tok::Semi || toks_[pos_ - 1].kind == Tok::LBrace ||
                    toks_[pos_ - 1].kind == Tok::RBrace;
  if (at(Tok::Number))
    return line_start && (peek().text == "0" || peek().text == "1") && peek(1).kind == Tok::Ident;
  return line_start && statement_word();
}

bool Cursor::statement_word(std::size_t k) const {
  const Token& t = peek(k);
  if (t.kind != Tok::Ident) return false;
  if (kElementKinds.count(t.text)) return true;
  auto shaped = kShapedKeywords.find(t.text);
  if (shaped == kShapedKeywords.end()) return kKeywords.count(t.text) > 0;
  return peek(k + 1).kind == shaped->second && peek(k + 1).loc.line == t.loc.line;
}

bool Cursor::new_statement_here() const {
  if (!at(Tok::Ident) || pos_ == 0 || toks_[pos_ - 1].loc.line == peek().loc.line) return false;
  return statement_word() && (peek(1).kind == Tok::Ident || kShapedKeywords.count(peek().text));
}

}  // namespace mbgc::parse
