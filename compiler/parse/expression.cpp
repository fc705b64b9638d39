#include "parse/expression.hpp"

#include <fmt/format.h>

#include "units/unit.hpp"

namespace mbgc::parse {

using ir::AstExpr;
using ir::AstExprPtr;

/// A name. Inside a for loop it may interpolate: `link{i-1}`, `n{i}_{j}`.
Name ExpressionParser::name(const char* what_for, const std::string& hint) {
  const Token& first = expect(Tok::Ident, what_for, hint);
  Name n{first.text, first.loc};
  const Token* last = &first;
  if (for_depth_ == 0) {
    // `link{i}` outside a loop: a block cannot start with `i }` or `i - 1`.
    if (at(Tok::LBrace) && adjacent(*last, peek()) && (peek(1).kind == Tok::Ident || peek(1).kind == Tok::Number) &&
        peek(2).kind != Tok::Assign && peek(2).kind != Tok::Ident)
      fail(fmt::format("a name can interpolate `{}{{...}}` only inside a for loop", first.text),
           "write the name in full here; or put a space before `{` to open a block");
    return n;
  }
  while (at(Tok::LBrace) && adjacent(*last, peek())) {
    const Token& open = next();
    std::size_t from = pos_;
    try {
      if (at(Tok::RBrace)) {
        ir::SourceLoc empty = open.loc;
        extend(empty, peek().loc);
        diags_.error(empty, fmt::format("empty interpolation in `{}{{}}`", n.text),
                     "write the index inside the braces, e.g. link{i}");
        throw ParseError{};
      }
      expr();  // checked here, evaluated by elaborate
      if (!at(Tok::RBrace)) {
        std::string so_far = n.text + "{";
        for (std::size_t k = from; k < pos_; ++k) so_far += toks_[k].text;
        fail(fmt::format("expected `}}` to close the interpolation in `{}`, found {}", so_far, describe(peek())),
             "an interpolated name is written name{expression}, e.g. link{i-1}; to open a block "
             "instead, put a space before `{`");
      }
    } catch (const ParseError&) {
      skip_interpolation(open);
      throw;
    }
    n.text += "{";
    for (std::size_t k = from; k < pos_; ++k) n.text += toks_[k].text;
    n.text += "}";
    last = &next();
    if (at(Tok::Ident) && adjacent(*last, peek())) {  // `n{i}_tip`
      last = &next();
      n.text += last->text;
    }
  }
  extend(n.loc, last->loc);
  return n;
}

/// After an error inside the interpolation opened by `open`: skip past its
/// `}` if that closes on the same line, so that recovery does not take it for
/// the end of the enclosing loop (`R fr{ e = f }` meant as a block).
void ExpressionParser::skip_interpolation(const Token& open) {
  int depth = 1;
  for (std::size_t k = pos_; toks_[k].kind != Tok::End && toks_[k].loc.line == open.loc.line; ++k) {
    if (toks_[k].kind == Tok::LBrace) ++depth;
    if (toks_[k].kind == Tok::RBrace && --depth == 0) {
      pos_ = k + 1;
      return;
    }
  }
}

/// A dotted path (`crank.a`, `m1.loop.f`); each part may interpolate inside a loop.
ir::AstEndpoint ExpressionParser::endpoint(const char* what_for) {
  Name first = name(what_for);
  ir::AstEndpoint e{first.text, first.loc};
  while (at(Tok::Dot)) {
    next();
    Name part = name("after `.`");
    e.path += "." + part.text;
    extend(e.loc, part.loc);
  }
  return e;
}

std::shared_ptr<AstExpr> ExpressionParser::make(AstExpr::Kind k, ir::SourceLoc loc) {
  auto e = std::make_shared<AstExpr>();
  e->kind = k;
  e->loc = loc;
  return e;
}

AstExprPtr ExpressionParser::binary(char op, ir::SourceLoc loc, AstExprPtr a, AstExprPtr b) {
  auto e = make(AstExpr::Kind::Binary, loc);
  e->op = op;
  e->args = {std::move(a), std::move(b)};
  return e;
}

AstExprPtr ExpressionParser::expr() {
  if (++depth_ > 200) fail("expression nested too deeply", "split it into parameters or signals");
  AstExprPtr lhs = product();
  while (at(Tok::Plus) || at(Tok::Minus)) {
    const Token& op = next();
    lhs = binary(op.text[0], op.loc, lhs, product());
  }
  --depth_;
  return lhs;
}

AstExprPtr ExpressionParser::product() {
  AstExprPtr lhs = unary();
  while (at(Tok::Star) || at(Tok::Slash)) {
    const Token& op = next();
    lhs = binary(op.text[0], op.loc, lhs, unary());
  }
  return lhs;
}

AstExprPtr ExpressionParser::unary() {
  if (at(Tok::Minus) || at(Tok::Plus)) {
    if (++depth_ > 200) fail("expression nested too deeply", "split it into parameters or signals");
    const Token& op = next();
    auto e = make(AstExpr::Kind::Unary, op.loc);
    e->op = op.text[0];
    e->args = {unary()};
    // the caret of `-1e12` or `-x` covers the sign and its operand (an
    // operator's own location is its symbol, so a longer operand keeps the sign's)
    const AstExpr& a = *e->args[0];
    const bool leaf = a.kind == AstExpr::Kind::Number || a.kind == AstExpr::Kind::Name || a.kind == AstExpr::Kind::Unary;
    if (leaf && a.loc.file == op.loc.file && a.loc.line == op.loc.line && a.loc.col > op.loc.col)
      e->loc.length = a.loc.col + a.loc.length - op.loc.col;
    --depth_;
    return e;
  }
  return power();
}

AstExprPtr ExpressionParser::power() {
  AstExprPtr base = postfix();
  if (at(Tok::Caret)) {
    const Token& op = next();
    if (++depth_ > 200) fail("expression nested too deeply", "split it into parameters or signals");
    AstExprPtr exponent = unary();  // right-associative: a^b^c = a^(b^c); a^-1 allowed
    --depth_;
    return binary('^', op.loc, base, exponent);
  }
  return base;
}

AstExprPtr ExpressionParser::postfix() {
  AstExprPtr e = primary();
  while (at(Tok::LBracket)) {
    ir::SourceLoc loc = next().loc;
    auto idx = make(AstExpr::Kind::Index, loc);
    idx->args.push_back(e);
    idx->args.push_back(expr());
    if (accept(Tok::Comma)) idx->args.push_back(expr());
    expect(Tok::RBracket, "to close the index");
    e = idx;
  }
  return e;
}

AstExprPtr ExpressionParser::primary() {
  const Token& t = peek();
  if (t.kind == Tok::String) {  // a file name; the passes that read one take it, others reject it
    next();
    auto e = make(AstExpr::Kind::String, t.loc);
    e->name = t.text;
    return e;
  }
  if (t.kind == Tok::Number) {
    next();
    auto e = make(AstExpr::Kind::Number, t.loc);
    e->number = t.number;
    if (at_unit()) {  // `30 {deg}`: kept in SI
      e->unit = unit();
      e->written = t.number;
      e->number = t.number * e->unit->unit.scale;
    }
    return e;
  }
  if (t.kind == Tok::Ident) {
    // `R load` here means the previous line's expression is unfinished.
    if (new_statement_here())
      fail(fmt::format("expected an expression, found the start of a statement (`{} {}`)", t.text, peek(1).text),
           "the expression before it is incomplete");
    ir::AstEndpoint path = endpoint("");
    if (at(Tok::LParen)) {
      next();
      auto e = make(AstExpr::Kind::Call, path.loc);
      e->name = path.path;
      while (!at(Tok::RParen)) {
        e->args.push_back(expr());
        if (!accept(Tok::Comma)) break;
      }
      expect(Tok::RParen, fmt::format("to close the call of `{}`", path.path).c_str());
      return e;
    }
    auto e = make(AstExpr::Kind::Name, path.loc);
    e->name = path.path;
    return e;
  }
  if (t.kind == Tok::LParen) {
    next();
    AstExprPtr e = expr();
    expect(Tok::RParen, "to close `(`");
    return e;
  }
  if (t.kind == Tok::LBracket) {
    next();
    auto e = make(AstExpr::Kind::List, t.loc);
    while (!at(Tok::RBracket)) {
      e->args.push_back(expr());
      if (!accept(Tok::Comma)) break;
    }
    expect(Tok::RBracket, "to close the list", "write vectors as [a, b, c] and matrices as [[a, b], [c, d]]");
    return e;
  }
  fail(fmt::format("expected an expression, found {}", describe(t)),
       "an expression is a number, a name, a call like sin(x), or (...)");
}

std::optional<ir::AstUnit> ExpressionParser::declared_unit(const AstExprPtr& value) {
  if (at_unit()) return unit();
  if (!value || value->kind == AstExpr::Kind::Number) return std::nullopt;
  if (value->kind == AstExpr::Kind::Unary && value->args[0]->kind == AstExpr::Kind::Number) return std::nullopt;
  // the last literal of a longer value, when its braces end the declaration
  AstExprPtr last = value;
  while (last->kind == AstExpr::Kind::Binary || last->kind == AstExpr::Kind::Unary) last = last->args.back();
  if (last->kind != AstExpr::Kind::Number || !last->unit) return std::nullopt;
  auto literal = std::const_pointer_cast<AstExpr>(last);  // made by this parser
  std::optional<ir::AstUnit> u = std::move(literal->unit);
  literal->unit.reset();
  literal->number = literal->written;
  return u;
}

bool ExpressionParser::at_unit() const {
  if (!units_here_ || !at(Tok::LBrace)) return false;
  const int line = peek().loc.line;
  for (std::size_t k = 1;; ++k) {
    const Token& t = peek(k);
    if (t.loc.line != line) return false;
    switch (t.kind) {
      case Tok::RBrace: return k > 1;
      case Tok::Ident: case Tok::Number: case Tok::Star: case Tok::Slash: case Tok::Caret:
      case Tok::Dot: case Tok::LParen: case Tok::RParen: case Tok::Minus: case Tok::Plus: break;
      default: return false;
    }
  }
}

ir::AstUnit ExpressionParser::unit() {
  const Token& open = next();
  // the text between the braces, spaced as written, so that an error's offset is a column
  const int first_col = open.loc.col + 1;
  std::string text;
  ir::SourceLoc loc = peek().loc;
  while (!at(Tok::RBrace)) {
    const Token& t = next();
    text.resize(static_cast<std::size_t>(t.loc.col - first_col), ' ');
    text += t.text;
    extend(loc, t.loc);
  }
  next();
  units::UnitParse parsed = units::parse_unit(text);
  if (!parsed.unit) {
    ir::SourceLoc at = open.loc;
    at.col = first_col + static_cast<int>(parsed.error.at);
    at.length = static_cast<int>(parsed.error.length);
    diags_.error(at, parsed.error.message, parsed.error.hint);
    throw ParseError{};
  }
  parsed.unit->text = text.substr(text.find_first_not_of(' '));
  return {*parsed.unit, loc};
}

}  // namespace mbgc::parse
