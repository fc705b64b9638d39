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
};

}  // namespace mbgc::ir
