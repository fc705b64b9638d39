// ir/equations.hpp — the equation system: scalar relations lhs == rhs, each
// assigned (by causality) to the one unknown it computes. Produced by
// equations, reduced by reduce.
#pragma once

#include <string>
#include <vector>

#include "ir/causal.hpp"

namespace mbgc::ir {

struct Equation {
  Expr lhs;
  Expr rhs;
  int unknown = -1;     // variable this equation computes
  SourceLoc loc;        // model line it came from
  std::string origin;   // e.g. "I armature_l: f = p / L" (for comments and dumps)
  bool constraint = false;  // lhs == rhs holds, but does not contain `unknown` (a CN's
                            // multiplier): reduce makes it a DAE residual
  bool in_loop = false;     // ... unless it is a stabilised CN's (acceleration level): then
                            // it is solved with the algebraic loop it belongs to
};

/// One holonomic constraint row of a CN: position level g(states) = 0 and
/// velocity level gdot = the CN's flow. Lagrange rows are enforced (their
/// multiplier is `multiplier`); penalty rows are only monitored.
struct ConstraintRow {
  std::string name;     // "j1.cn[2]"
  SourceLoc loc;
  Expr g;               // in terms of states
  int flow = -1;        // variable holding dg/dt (the CN's flow)
  int multiplier = -1;  // lagrange: the CN's effort variable; -1 for penalty
  Expr gdot;            // set by reduce: the flow after alias elimination
  int stabiliser = -1;  // set by reduce (lagrange, DAE): the GGL multiplier mu of the row
  bool cut = false;     // a cut joint's row (joint coordinates): held by Baumgarte's g'' + 2 w g' + w^2 g = 0
};

/// A contact: a CN whose row g >= 0 acts only while closed (LawForm::Unilateral,
/// Compliant). Its mode and the values the runtime sets at its events are
/// discrete variables; the runtime switches them where the event function
/// crosses zero (reduce/events adds one event per contact).
struct ContactRow {
  std::string name;     // the CN's: "hit.cn"
  SourceLoc loc;
  bool compliant = false;
  Expr gap;             // g, position level (states and pose signals)
  Expr rate;            // dg/dt (the CN's flow, signed); reduce replaces it by its value after aliases
  Expr normal_force;    // the push, >= 0 while closed: +-e of the CN (its effort variable)
  Expr restitution;     // parameters only
  int closed = -1;      // discrete: 1 while in contact
  int bias = -1;        // discrete, unilateral: added to the row's g'' (the runtime's probe for impulses)
  int damping = -1;     // discrete, compliant: Hunt-Crossley's chi / v- (set when the contact closes)
  // Unilateral with friction: rows 2 and 3 are tangential. While stuck
  // (`stick` = 1) their rate is held at 0; while sliding the friction is
  // -mu * push along the slip direction (slip1, slip2 in the rows' tangent basis).
  Expr friction;        // mu (parameters only); null: frictionless
  int stick = -1, slip1 = -1, slip2 = -1;  // discrete
  Expr tangent_rate[2];   // the sliding velocity along the two tangents
  Expr tangent_force[2];  // the friction on the first side along them (-s e)
};

struct StateVar {
  int var = -1;         // the state (momentum p, displacement q)
  int der = -1;         // its time derivative variable
  int node = -1;        // the storage element
  Expr initial;         // initial value (parameters only)
};

struct EquationSystem {
  BondGraph graph;
  CausalityReport causality;
  std::vector<StateVar> states;
  std::vector<Equation> equations;
  std::vector<ConstraintRow> constraints;
  std::vector<ContactRow> contacts;
};

}  // namespace mbgc::ir
