// codegen/shared_values.hpp — what several methods compute alike, written once.
//
// The energy witness's power() and stored_energy() both need the bodies'
// velocities: written separately, each method carried its own copy of that
// kinematics. This pass takes the assignments the methods share and which
// of the variables they define the methods read (their results and their own
// remaining assignments); the emitter writes those assignments once, in a
// private method that each of them calls first, keeps what they read in
// members, and writes each method's remaining assignments in the method
// (codegen/emit_cpp.cpp). Shared are either all the assignments either
// method needs (their union: the file is smallest, nothing is left to the
// methods) or only those both need (their intersection): the emitter takes
// the intersection where the union would more than double the work of
// stored_energy(), which runs at every output row (a flexible car's powers
// read its dynamics: with the union a row cost a derivative's worth).
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

enum class Sharing { all, common };  ///< the slices' union, their intersection

struct SharedValues {
  std::vector<int> assignments;      ///< indices into ReducedSystem::assignments, in causal order
  std::unordered_set<int> exported;  ///< the variables they define that the methods' results read

  bool empty() const { return assignments.empty(); }
  /// The assignments of `slice` (ascending) these do not compute.
  std::vector<int> rest_of(const std::vector<int>& slice) const;
};

/// The assignments of any of `slices` (Sharing::all) or of every one
/// (Sharing::common), in causal order, and those of their variables that
/// `results` or the slices' other assignments read.
SharedValues find_shared_values(const ir::ReducedSystem& s, const std::vector<const std::vector<int>*>& slices,
                                const std::vector<ir::Expr>& results, Sharing sharing);

}  // namespace mbgc::codegen
