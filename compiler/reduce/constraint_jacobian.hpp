// reduce/constraint_jacobian.hpp — pass 6c: G = dg/dx of the constraint rows.
//
// Each CN row's position-level g is an expression in the states, parameters
// and time, or (a cut joint of a tree in joint coordinates) in the pose
// signals the tree's assignments compute from the joint coordinates; its
// derivatives by the states are taken symbolically here, through those
// assignments (reduce/forward_diff.hpp). The runtime assembles the initial state and finds
// redundant rows with it (mbgrt::Model::constraint_jacobian) instead of
// differencing g.
#pragma once

#include <optional>

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Fills s.constraint_jacobian: per row of s.constraints, its nonzero
/// derivatives by the states, ascending in the state's index. Returns the
/// first row that reads a variable a linear block solves numerically (none
/// does: positions are found without solves), or nothing.
std::optional<std::size_t> constraint_jacobian(ir::ReducedSystem& s);

}  // namespace mbgc::reduce
