// ir/constant.hpp — the value of an AST expression at compile time: numbers,
// names the caller resolves, + - * / ^ and, where the caller allows them, pi
// and the scalar functions of one argument. The one constant evaluator:
// elaboration's loop bounds and name indices (with diagnostics), the
// multibody layer's constant settings and a drawn surface's sizes (silent:
// an expression with no constant value is simply not a constant there).
#pragma once

#include <climits>
#include <functional>
#include <optional>

#include "ir/ast.hpp"

namespace mbgc::ir {

/// Why a sub-expression has no constant value of its own (its operands had).
enum class NotConstant {
  division_by_zero,  ///< a / b with b = 0
  form,              ///< not arithmetic: a call not allowed, a list, an index, a string
};

struct ConstantRules {
  /// The value of a name (a parameter, a loop variable), or nullopt when it
  /// has none (the callback reports that itself, if it should). `depth` is
  /// the nesting of the name in the evaluation; a name's definition
  /// evaluated by the callback goes on at depth + 1.
  std::function<std::optional<double>(const AstExpr& name, int depth)> name;
  /// Also `pi` and sin, cos, tan, sqrt, atan, abs, exp, log of one argument.
  bool functions = false;
  /// Deeper sub-expressions than this have no value (a guard against a
  /// definition that refers back to itself, for callers that do not detect it).
  int max_depth = INT_MAX;
  /// Called at each sub-expression that has no value for a reason of its
  /// own; optional.
  std::function<void(const AstExpr& at, NotConstant why)> failed;
};

/// The value of `e`, or nullopt. Both operands of an operator are evaluated
/// even when the first has no value, so that each failure is reported.
std::optional<double> constant_value(const AstExpr& e, const ConstantRules& rules, int depth = 0);

}  // namespace mbgc::ir
