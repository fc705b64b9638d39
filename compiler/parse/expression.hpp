// parse/expression.hpp — expressions, names and units of the .mbg language
// (used only by the parser; the statements are in parse.cpp).
//
// Inside a `for` loop a name may interpolate `{expr}` (`link{i-1}.tip`): an
// identifier immediately followed by `{` (no whitespace) starts one. The name's
// text keeps "{expr}" verbatim, whitespace removed; elaborate substitutes it.
//
// A unit in braces follows a literal (`3 {kg}`, `30 {deg}`) or ends a
// declaration (`param k = m*g/x0 {N/m}`, `param m = 12 * I / a^2 {kg}`):
// braces on one line holding only symbols, numbers and `* . / ^ ( ) -` (a
// block of settings holds `=`).
// A literal's value is kept in SI (`30 {deg}` is 0.5236), what was typed beside it.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "parse/cursor.hpp"

namespace mbgc::parse {

class ExpressionParser : protected Cursor {
 public:
  using Cursor::Cursor;

 protected:
  /// A name. Inside a for loop it may interpolate: `link{i-1}`, `n{i}_{j}`.
  Name name(const char* what_for, const std::string& hint = {});
  /// A dotted path (`crank.a`, `m1.loop.f`); each part may interpolate inside a loop.
  ir::AstEndpoint endpoint(const char* what_for);

  ir::AstExprPtr expr();
  /// A declaration's unit: `{N/m}` after its value, or the braces that end a
  /// value of more than one literal (`param m2 = 12 * I2 / a2^2 {kg}` is
  /// kg, not a squared 2 kg); a lone literal keeps its own (`1400 {kg}`).
  std::optional<ir::AstUnit> declared_unit(const ir::AstExprPtr& value);

  int depth_ = 0;        // expression nesting
  int for_depth_ = 0;    // for-loop nesting: names interpolate inside a loop
  bool units_here_ = true;  // off in a loop's bounds, whose `{` opens the body

 private:
  void skip_interpolation(const Token& open);
  /// A new node of kind `k` at `loc`, to be filled in.
  static std::shared_ptr<ir::AstExpr> make(ir::AstExpr::Kind k, ir::SourceLoc loc);
  static ir::AstExprPtr binary(char op, ir::SourceLoc loc, ir::AstExprPtr a, ir::AstExprPtr b);
  ir::AstExprPtr product();
  ir::AstExprPtr unary();
  ir::AstExprPtr power();
  ir::AstExprPtr postfix();
  ir::AstExprPtr primary();
  /// The braces at the cursor hold a unit (see above).
  bool at_unit() const;
  /// `{unit}` at the cursor, read and checked.
  ir::AstUnit unit();
};

}  // namespace mbgc::parse
