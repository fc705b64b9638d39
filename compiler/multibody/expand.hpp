// multibody/expand.hpp — pass 1c: bodies and joints -> multibond-graph fragments.
//
// Every `body` becomes the rigid-body multibond graph of the thesis (§2.6,
// Fig. 2-3): a 3-dimensional 1-junction for the centre-of-mass velocity
// (inertial frame) with the mass I, the weight Se and a C (e = 0) that
// integrates the position; a 1-junction for the angular velocity (body frame)
// with the inertia tensor I, the Euler junction structure (the gyrating
// resistor e = omega x h, power-free) and a modulated transformer that feeds
// the Euler-parameter (quaternion) rates q' = E(q) omega into a 4-dimensional
// C (e = 0). A body without `inertia` is a particle (translation only).
//
// Every `joint` is a set of holonomic constraint rows g(positions) = 0 written
// with the joint frames of both bodies. Their rates are collected on a
// 0-junction from one modulated transformer per body junction (modulus
// dg/dr and dg/dq E(q), by symbolic differentiation), and a constraintor CN
// (§7.3) closes it: `lagrange` (multipliers, a DAE) or `penalty` (stiff
// spring-damper on g). A joint's drive port `j.drive` is a 1-junction whose
// flow is the joint rate, built the same way from the joint coordinate.
//
// Initial positions and velocities follow from the joint coordinates (q0,
// rate0) along a spanning tree from ground; loop-closing joints are closed by
// the runtime's assembly. Names users may read in expressions, such as
// `bob.position`, `crank.bryant` or `j1.angle`, are replaced here by their
// definitions. The result is a plain layer-1 program (`mbgc --dump=expanded`).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/expanded.hpp"

namespace mbgc::multibody {

/// How joint constraints are enforced (the model's `constraints = ...`).
/// `Auto` (the default) becomes Coordinates for a tree joint coordinates can
/// move, else Lagrange; ExpandOptions::strategy_report says which and why.
enum class Strategy { Auto, Lagrange, Penalty, Coordinates };
/// As the language spells it: "auto", "lagrange", "penalty", "coordinates".
inline const char* strategy_name(Strategy s) {
  switch (s) {
    case Strategy::Auto: return "auto";
    case Strategy::Lagrange: return "lagrange";
    case Strategy::Penalty: return "penalty";
    case Strategy::Coordinates: return "coordinates";
  }
  return "";
}

/// How contacts act (a contact's `strategy = ...`, or mbgc --contacts).
enum class ContactStrategy {
  Unilateral,  // a constraint row while it pushes; impacts by Newton's restitution law (an impulse)
  Compliant,   // a Hunt-Crossley force: its stiffness and the damping that gives its restitution
};

struct ExpandOptions {
  /// mbgc --constraints: replaces the model-level setting; a joint's own
  /// `constraint = ...` still wins over both.
  std::optional<Strategy> constraints;
  /// mbgc -I: directories searched for modal-data files after the model's own.
  std::vector<std::string> search_dirs;
  /// mbgc --contacts: the strategy of every contact that does not name its own.
  std::optional<ContactStrategy> contacts;
  /// If set: what `constraints = auto` chose and why (empty when no joint was
  /// left to auto), and the rotors (multibody/rotors.hpp).
  std::string* strategy_report = nullptr;
  /// false (mbgc --no-rotors): every body in its own frame, no rotors.
  bool rotors = true;
};

/// Modal-data files a model names (`flexible = modal("arm.mbm")`) are read
/// here and join `sources`.
ir::ExpandedProgram expand(const ir::AstProgram& program, ir::SourceManager& sources, ir::Diagnostics& diags,
                           const ExpandOptions& options = {});

}  // namespace mbgc::multibody
