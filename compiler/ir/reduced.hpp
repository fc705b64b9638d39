// ir/reduced.hpp — the sorted, simplified system the emitter prints.
#pragma once

#include <string>
#include <vector>

#include "ir/equations.hpp"

namespace mbgc::ir {

/// var := value, in evaluation order.
struct Assignment {
  int var = -1;
  Expr value;
  SourceLoc loc;
  std::string origin;
};

/// An algebraic loop found while sorting, in bond-graph terms.
struct AlgebraicLoop {
  std::vector<int> vars;       // unknowns of the loop
  std::vector<int> bonds;      // bond indices they belong to
  bool linear = true;
  std::string resolution;      // "solved symbolically" / "left to IDA as a DAE"
};

struct Residual {
  Expr value;                  // must vanish
  SourceLoc loc;
  std::string origin;
};

struct ReducedSystem {
  BondGraph graph;
  CausalityReport causality;
  std::vector<StateVar> states;
  std::vector<Expr> state_derivative;     // per state: what the integrator gets
  std::vector<Assignment> assignments;    // everything derivative/residual/outputs need, sorted
  std::vector<int> for_derivative;        // indices into assignments, in order
  std::vector<int> for_outputs;           // indices into assignments, in order
  // DAE form (dae == true): y = [states, algebraic], residuals in the same order.
  bool dae = false;
  std::vector<int> algebraic;             // algebraic unknowns (read from y)
  std::vector<int> derivative_unknowns;   // der vars read from yp (per state, -1 if computed)
  std::vector<Residual> residuals;
  std::vector<AlgebraicLoop> loops;
  std::vector<std::string> derivative_causality;  // how each derivative-causal storage was handled
  std::vector<std::string> log;           // what reduction did, one line per step
};

}  // namespace mbgc::ir
