// ir/value.hpp — shaped values (scalar, vector, matrix of expressions) and the
// lowering of expressions into them: AST expressions by name (resolve's
// parameters) and bound terms by reference (the graph's element laws,
// signals and outputs), with one set of rules.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/expr.hpp"
#include "ir/term.hpp"

namespace mbgc::ir {

/// rows x cols expressions, row-major. A scalar is 1x1; a vector is n x 1.
struct Value {
  int rows = 1;
  int cols = 1;
  std::vector<Expr> items;

  static Value scalar(Expr e) { return Value{1, 1, {std::move(e)}}; }
  bool is_scalar() const { return rows == 1 && cols == 1; }
  bool is_vector() const { return cols == 1 || rows == 1; }
  int length() const { return rows * cols; }
  const Expr& at(int r, int c) const { return items[static_cast<std::size_t>(r * cols + c)]; }
  std::string shape() const;
};

/// Resolves a (dotted) name at `loc` to a value; returns nullopt after having
/// reported an error.
using NameLookup = std::function<std::optional<Value>(const std::string& name, const SourceLoc& loc)>;

/// Resolves a term's ref (not t or pi, which lowering knows): `leaf` is the
/// Ref term, with its location (and, for a name, its text).
using RefLookup = std::function<std::optional<Value>(const Term& leaf)>;

/// Lower an AST expression. Reports shape errors, unknown functions and wrong
/// arity; returns nullopt on error.
std::optional<Value> lower(const AstExpr& e, const NameLookup& lookup, Diagnostics& diags);
/// Lower a bound term, as above.
std::optional<Value> lower(const Term& e, const RefLookup& lookup, Diagnostics& diags);

/// Names of the language's functions (for "did you mean").
std::vector<std::string> function_names();

}  // namespace mbgc::ir
