// reduce/tree_elimination.hpp — the algebraic loop of a kinematic tree in
// joint coordinates, eliminated body by body from the leaves to the root.
//
// In joint coordinates every body's inertia takes derivative causality and
// the bodies' accelerations, reaction efforts and joint accelerations form one
// linear algebraic loop. Tearing it at the joint accelerations gives the mass
// matrix system M(q) q'' = b: N^2 coefficients, O(N^3) work. The loop is
// sparse, though: a body's equations read only its own unknowns, its
// parent's (the accelerations its joint carries outward) and its children's
// (the reaction efforts they push inward). Eliminating it in the tree's order
// creates no fill (docs/notes/linear_time.md):
//
//   inward, leaves first: every unknown of body n is affine in its joint
//     accelerations T_n and its parent's unknowns X_n that it reads; its
//     joint's equations D T_n + C X_n + d = 0 give T_n = -D^-1 (C X_n + d),
//     so what its parent reads of it is K_n X_n + k_n (an articulated
//     inertia and bias, as named temporaries);
//   outward, root first: X_n is known, T_n follows, then the body's unknowns.
//
// For rigid bodies this is Featherstone's articulated-body algorithm; the
// same elimination takes flexible bodies' modal accelerations (more tears per
// body) and any bond-graph element whose unknowns join a body's block.
//
// Cut joints (loops on the tree): their multipliers Lambda are carried through
// the inward pass as more columns of every affine form (like X_n); after it,
// the unknowns their acceleration-level rows read are written affine in
// Lambda alone (one outward pass per column, along the paths to the root
// only), the m x m system for Lambda is solved at run time, and the outward
// pass follows as before.
#pragma once

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "ir/graph.hpp"
#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// A linear loop torn at its state derivatives.
struct TornLoop {
  std::vector<int> tears;                  // the state derivatives torn at
  std::vector<ir::Expr> tear_residuals;    // per tear: its equation as lhs - rhs (= 0)
  std::vector<int> order;                  // the other unknowns, each computable from the tears and earlier ones
  std::unordered_map<int, ir::Expr> solution;  // their explicit solutions
  std::unordered_map<int, std::pair<ir::SourceLoc, std::string>> source;  // per unknown: model line and origin
  // Tears that are cut joints' multipliers (their residuals, g'' = ..., read
  // bodies anywhere in the tree), not accelerations of a body.
  std::vector<int> multipliers;
};

/// The bodies of the tree and which body each variable belongs to.
using TreeLayout = ir::BodyTree;

struct TreeElimination {
  // In evaluation order: the inward temporaries; with cut joints, the
  // multipliers' columns (each unknown their equations read, affine in the
  // multipliers) and the multipliers themselves (block == 0: the system
  // `multipliers` below); then every other unknown.
  std::vector<ir::Assignment> assignments;
  std::optional<ir::LinearBlock> multipliers;  // the m x m system for the cut joints' multipliers, solved at run time
  int bodies = 0;                           // bodies of the tree in the loop
  int temporaries = 0;
  std::unordered_map<int, int> body_of;     // every unknown of the loop and temporary -> its body (not the multipliers)
};

/// The loop eliminated along the tree, or nullopt (with the reason in
/// `why_not`) when its structure is not a tree's: an unknown that belongs to
/// no body, or a body's equation reading a body other than itself, its
/// parent or its children. Temporaries are added to `graph`'s variables.
std::optional<TreeElimination> eliminate_along_tree(const TornLoop& loop, const TreeLayout& tree, ir::BondGraph& graph,
                                                    std::string* why_not);

}  // namespace mbgc::reduce
