// ir/value.hpp — shaped values (scalar, vector, matrix of expressions) and the
// lowering of AST expressions into them. Used by resolve (parameters) and by
// graph (element laws, signals, outputs), each with its own name lookup.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/expr.hpp"

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

/// Lower an AST expression. Reports shape errors, unknown functions and wrong
/// arity; returns nullopt on error.
std::optional<Value> lower(const AstExpr& e, const NameLookup& lookup, Diagnostics& diags);

/// Names of the language's functions (for "did you mean").
std::vector<std::string> function_names();

}  // namespace mbgc::ir
