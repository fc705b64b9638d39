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
};

}  // namespace mbgc::ir
