// ir/reduced.hpp — the sorted, simplified system the emitter prints.
#pragma once

#include <optional>
#include <unordered_map>

#include <string>
#include <string_view>
#include <vector>

#include "ir/equations.hpp"

namespace mbgc::ir {

/// var := value, in evaluation order. An unknown of a numerically solved
/// linear block has no value of its own: `block` names the block that
/// computes it (all of a block's unknowns are adjacent in the order).
struct Assignment {
  int var = -1;
  Expr value;          // null when block >= 0
  SourceLoc loc;
  std::string origin;
  int block = -1;      // index into ReducedSystem::linear_blocks
};

/// A linear algebraic loop A x = b whose symbolic pivots could vanish at run
/// time: the emitter fills A and b and calls mbgrt::solve_linear (partial pivoting).
struct LinearBlock {
  std::vector<int> unknowns;  // x
  std::vector<Expr> a;        // n x n, row-major
  std::vector<Expr> b;        // n
  // Cut joints' (and closed contacts') multipliers: their rows may become
  // dependent during a run (a parallelogram's links aligning):
  // mbgrt::solve_rank_revealing instead.
  bool rank_revealing = false;
  // Some of the rows are cut joints' (a CN of LawForm::Stabilised): where
  // they become dependent the mechanism is at a change point, which the run
  // watches for (RankLossLog::observe).
  bool cut_joints = false;
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

/// A kinematic tree in joint coordinates whose loop was eliminated along it
/// (reduce/tree_elimination): its bodies and which body each variable
/// belongs to (the emitter groups a body's equations by it, codegen/outline).
struct BodyTree {
  std::vector<std::string> names;        // per body
  std::vector<int> parent;               // per body: its parent body, -1 for ground
  std::unordered_map<int, int> body_of;  // variable id -> body (variables not listed: none, or unknown)
};

/// What every temporary of a tree elimination's origin starts with
/// (reduce/tree_elimination); the emitter groups a body's equations by it.
inline constexpr std::string_view kTreeEliminationOrigin = "articulated-body elimination";
inline bool from_tree_elimination(const Assignment& a) { return a.origin.starts_with(kTreeEliminationOrigin); }

/// A discontinuity of the model: step(arg), held as a mode (0 or 1) between
/// the zero crossings of arg, which the integrators locate (reduce/events).
struct EventRelation {
  Expr step;              // the step(arg) node, printed as its mode
  Expr arg;               // the zero-crossing function
  bool time_event = false;  // arg is a function of time alone: its crossings are known in advance
  SourceLoc loc;            // the model line of the first equation it is in (invalid: none has one)
  std::string origin;       // that equation's origin ("Sf src: f = value")
  int contact = -1;         // a contact's event (ReducedSystem::contacts): step is its `closed` variable and
                            // arg its gap while open, its normal force while a unilateral one is closed
  bool friction = false;    // ... or its friction's: step is its `stick` variable (reduce/events.cpp)
};

/// One storage's energy, or one element's power (reduce/energy.hpp).
struct EnergyTerm {
  Expr value;
  SourceLoc loc;        // the element's declaration
  std::string origin;   // "R damper: power in, e.f"
};

/// The energy balance the runtime checks as a witness (reduce/energy.hpp):
/// H = sum of `stored` (at the output points, after the assignments in
/// ReducedSystem::for_energy) against the integrals of the `supplied` and
/// `absorbed` powers (after ReducedSystem::for_power), which the runtime's
/// integrators carry beside the state.
struct EnergyBalance {
  bool available = false;
  std::string why_not;                   // when not available
  std::vector<EnergyTerm> stored;        // per linear storage, a function of the state
  std::vector<EnergyTerm> supplied;      // per source: the power it delivers
  std::vector<EnergyTerm> absorbed;      // per R, CN, nonlinear storage: the power into it
  std::vector<std::string> unwitnessed;  // storages counted by their power, and why
};

/// The variables an assignment reads (its value, or its whole block).
void assignment_inputs(const struct ReducedSystem& s, const Assignment& a, std::unordered_set<int>& out);

struct ReducedSystem {
  BondGraph graph;
  CausalityReport causality;
  std::vector<StateVar> states;
  std::vector<Expr> state_derivative;     // per state: what the integrator gets
  std::vector<Expr> nominal;              // per state: its size, in parameters (reduce/nominal.hpp)
  std::vector<Assignment> assignments;    // everything derivative/residual/outputs need, sorted
  std::vector<LinearBlock> linear_blocks; // loops solved numerically (see Assignment::block)
  std::vector<int> for_derivative;        // indices into assignments, in order
  std::vector<int> for_position_rates;    // ... what the position states' derivatives need (an ODE's; the symplectic Euler's)
  std::vector<int> for_outputs;           // indices into assignments, in order
  std::vector<int> for_drawings;          // ... what the drawn bodies' poses need
  // d(state derivative i)/d(state j), row-major n x n, for ODEs whose loops are
  // all solved symbolically (empty otherwise: the solver uses finite differences).
  std::vector<Expr> jacobian;
  std::vector<int> for_jacobian;          // indices into assignments, in order
  // DAE form (dae == true): y = [states, algebraic], residuals in the same order.
  bool dae = false;
  std::vector<int> algebraic;             // algebraic unknowns (read from y)
  std::vector<int> derivative_unknowns;   // DAE: per state, the variable read from yp[i]
  std::vector<Residual> residuals;
  // DAE: per column k of IDA's matrix dF/dy + c_j dF/dy', the residual rows
  // that read y_k or y'_k, ascending (reduce/sparsity.hpp).
  std::vector<std::vector<int>> residual_pattern;
  // Holonomic constraints of the CN elements (g in states, gdot after the
  // assignments in for_constraints): enforced by the DAE for lagrange rows
  // (stabilised index-2: residuals gdot = 0 and g = 0, multipliers lambda and
  // mu), monitored for penalty rows.
  std::vector<ConstraintRow> constraints;
  std::vector<int> for_constraints;       // indices into assignments, in order
  // G = dg/dx: per constraint row, its nonzero derivatives by the states, by
  // row, then state (reduce/constraint_jacobian), after the assignments in
  // for_constraint_jacobian (a cut joint's g reads the tree's pose signals).
  struct JacobianEntry {
    int row = -1;    // index into constraints
    int state = -1;  // index into states
    Expr value;
  };
  std::vector<JacobianEntry> constraint_jacobian;
  std::vector<int> for_constraint_jacobian;  // indices into assignments, in order
  EnergyBalance energy;                   // the energy witness (reduce/energy)
  std::vector<int> for_energy;            // indices into assignments, in order: what the stored energy needs
  std::vector<int> for_power;             // ... what the two powers need
  std::vector<EventRelation> events;      // the model's discontinuities (reduce/events)
  std::vector<int> for_events;            // indices into assignments, in order: what the events' args need
  std::vector<ContactRow> contacts;       // contacts (CN with a restitution), each with its event
  std::vector<int> for_contacts;          // indices into assignments, in order: what the contacts' rates need
  std::vector<int> for_tangents;          // ... and their tangential rows' rates and efforts (friction)
  std::vector<AlgebraicLoop> loops;
  std::optional<BodyTree> tree;           // set when a loop was eliminated along a kinematic tree
  std::vector<std::string> derivative_causality;  // how each derivative-causal storage was handled
  std::vector<std::string> log;           // what reduction did, one line per step
};

/// Whether state i is a position (the q of a C: a displacement, an angle, a
/// modal coordinate, a charge), else a velocity (the p of an I, an
/// independent joint rate): the layout the runtime is told (Model::unknown_role).
inline bool is_position_state(const ReducedSystem& s, std::size_t i) {
  return s.graph.nodes[static_cast<std::size_t>(s.states[i].node)].kind == NodeKind::C;
}

}  // namespace mbgc::ir
