// reduce/forward_diff.hpp — derivatives by the states through the assignments.
//
// Forward-mode symbolic differentiation: the derivative of an expression by
// each state is the sum, over the variables it reads, of its partial
// derivative by the variable times that variable's own derivatives (the
// chain rule), a state's being 1 by itself and an assignment's those of its
// value. Each variable's derivatives are worked out once. The results refer
// to assignment variables, so the emitter computes them after the same
// assignments. Used for the ODE Jacobian (reduce.cpp) and for G = dg/dx
// (constraint_jacobian.cpp).
#pragma once

#include <map>
#include <optional>
#include <unordered_map>

#include "ir/reduced.hpp"

namespace mbgc::reduce {

class ForwardDiff {
 public:
  /// Nonzero derivatives by state index (into s.states), ascending.
  using Derivatives = std::map<int, ir::Expr>;

  explicit ForwardDiff(const ir::ReducedSystem& s);

  /// The derivatives of e by the states; nothing if e depends on a variable
  /// a numerically solved linear block computes (no expression to differentiate).
  std::optional<Derivatives> of(const ir::Expr& e);

 private:
  const Derivatives* of_var(int id);

  std::unordered_map<int, int> state_index_;
  std::unordered_map<int, const ir::Assignment*> assignment_of_;
  std::unordered_map<int, std::optional<Derivatives>> memo_;
};

}  // namespace mbgc::reduce
