// multibody/shapes.hpp — what the text tells of a value before any run: its
// shape (rows and columns) and, where it is a constant, its number, through
// the model's top-level parameters by their definitions. The collect pass
// checks settings with it; the drawings read their sizes with it.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>

#include "ir/ast.hpp"
#include "ir/constant.hpp"
#include "multibody/build.hpp"
#include "multibody/settings.hpp"

namespace mbgc::multibody::detail {

class Constants {
 public:
  /// Over `params`, the program's top-level parameters (kept by reference).
  explicit Constants(const std::map<std::string, ir::AstExprPtr>& params) : params_(params) {}

  /// The shape of `e` if it follows from numbers, lists, parameters and the
  /// built-in functions; nullopt when it cannot be told here (checked later).
  std::optional<Shape> shape_of(const ir::AstExpr& e, int depth = 0) const;
  /// The value of `e` if it is a constant: numbers, parameters and + - * / ^.
  std::optional<double> constant_of(const ir::AstExpr& e, int depth = 0) const;
  /// As constant_of, also through the functions and `pi` a surface's
  /// settings may use (the snap-fit's ramp: tan(alpha * pi / 180)).
  std::optional<double> drawn_number(const ir::AstExpr& e, int depth = 0) const;
  /// A 3-vector of constants (a point), also through a parameter.
  std::optional<std::array<double, 3>> constant_point(const ir::AstExpr& e, int depth = 0) const;
  static bool mentions_time(const ir::AstExpr& e);

 private:
  /// ir::constant_value's rules here: parameters by their definitions, to
  /// kMaxDepth levels (a definition that refers back to itself has no
  /// value); with `functions`, also pi and the scalar functions.
  ir::ConstantRules rules(bool functions) const;
  static constexpr int kMaxDepth = 50;
  const std::map<std::string, ir::AstExprPtr>& params_;
};

}  // namespace mbgc::multibody::detail
