// codegen/shared_values.hpp — what several methods compute alike, written once.
//
// The energy witness's power() and stored_energy() both need the bodies'
// velocities and, for the powers, the forces on them: written separately,
// each method carried its own copy of that kinematics. This pass takes the
// assignments the methods need (the union of their slices) and which of the
// variables they define the methods' results read; the emitter writes those
// assignments once, in a private method that each of them calls first, and
// keeps what the results read in members (codegen/emit_cpp.cpp).
//
// derivative() keeps its own copy: called by kinematics it ran 8 % slower on
// the 100-rod chain (values through members instead of registers), and the
// dynamics' speed is the product's.
#pragma once

#include <unordered_set>
#include <vector>

#include "ir/expr.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

struct SharedValues {
  std::vector<int> assignments;      ///< indices into ReducedSystem::assignments, in causal order
  std::unordered_set<int> exported;  ///< the variables they define that the methods' results read

  bool empty() const { return assignments.empty(); }
};

/// The assignments of all `slices` (each closed under what its assignments
/// read, so is their union), in causal order, and those of their variables
/// that `results` read.
SharedValues find_shared_values(const ir::ReducedSystem& s, const std::vector<const std::vector<int>*>& slices,
                                const std::vector<ir::Expr>& results);

}  // namespace mbgc::codegen
