// ir/graph.hpp — the flattened multibond graph: nodes (elements, junctions),
// directed bonds (power from `from` to `to`) with dimensions, and the scalar
// variables every later pass refers to by id. Produced by graph, annotated by
// causality, read by equations and emit.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ir/declared_unit.hpp"
#include "ir/diagnostics.hpp"
#include "ir/drawing.hpp"
#include "ir/expr.hpp"
#include "ir/value.hpp"

namespace mbgc::ir {

/// CN is the constraintor (thesis §7.3): a one-port that keeps its flow at zero
/// (`lagrange`: its effort is an unknown multiplier) or pulls it back with a
/// stiff spring-damper on the position-level constraint g (`penalty`).
enum class NodeKind { Se, Sf, I, C, R, TF, GY, MTF, MGY, Zero, One, CN };

const char* node_kind_name(NodeKind k);  // "Se", ..., "0", "1"
inline bool is_junction(NodeKind k) { return k == NodeKind::Zero || k == NodeKind::One; }
inline bool is_two_port(NodeKind k) {
  return k == NodeKind::TF || k == NodeKind::GY || k == NodeKind::MTF || k == NodeKind::MGY;
}
inline bool is_storage(NodeKind k) { return k == NodeKind::I || k == NodeKind::C; }

/// How a one-port's constitutive law was given.
enum class LawForm {
  Linear,          // value is a scalar or n x n matrix (R: e = R f; I: p = I f; C: q = C e)
  EffortOfFlow,    // R { e = phi(f) }
  FlowOfEffort,    // R { f = phi(e) }
  EffortOfState,   // C { e = phi(q) }
  FlowOfState,     // I { f = phi(p) }
  Source,          // Se/Sf: value is the imposed effort/flow (any expression)
  Constraint,      // CN, lagrange: f = 0, e is an unknown multiplier
  Penalty,         // CN, penalty: e = stiffness * g + damping * f
  Stabilised,      // CN, a cut joint on a tree in joint coordinates: e is a multiplier that keeps
                   // der(f) + 2 w f + w^2 g = 0 (Baumgarte; w = law_rhs[0]); g may read signals
  Unilateral,      // CN with a restitution: a contact, g >= 0. While closed (a mode the runtime
                   // switches) e keeps g'' + 2 w g' + w^2 g = 0 as Stabilised does, while open
                   // e = 0; impacts are impulses by Newton's law (law_rhs = {w, restitution[,
                   // friction]}). With friction, rows 2 and 3 are tangential: while stuck their
                   // rate is held at 0, while sliding e is Coulomb's mu * push along the slip
  Compliant,       // CN with a restitution and a stiffness: a contact whose e is a Hunt-Crossley
                   // force while g < 0, 0 otherwise (law_rhs = {stiffness, exponent, restitution})
  FreeRate,        // Sf { rate0 = ... }: the flow is a state (an independent joint rate) and
                   // the effort must vanish; the rate's derivative is found from e = 0
};

struct GraphNode {
  NodeKind kind = NodeKind::Zero;
  std::string name;        // full path, e.g. "m1.rotor"
  SourceLoc loc;           // of the declaration's name
  int dim = 1;             // multibond dimension (two-ports: of port 1)
  int dim2 = 1;            // two-ports: dimension of port 2
  std::vector<int> bonds;  // attached bond indices (two-ports: [port1, port2])
  // Constitutive law (elements only):
  LawForm law = LawForm::Linear;
  Value value;             // modulus / parameter / source value (shaped)
  std::vector<Expr> law_rhs;  // nonlinear law right-hand side, one per component
  Value constraint_g;      // CN: the position-level constraint g(states), dim x 1 (f = dg/dt)
  Value initial;           // initial state (storage elements), shaped dim x 1
  bool initial_is_state = false;  // given as the state itself (q0, p0, rate0), not through e0 or f0
  std::vector<int> state_vars;  // storage: one variable per component
  // A contact CN's discrete variables (VarKind::Discrete): closed, then bias
  // (unilateral) or damping (compliant), then stick, slip[1], slip[2] (friction).
  std::vector<int> discrete;
  std::vector<std::pair<double, std::string>> state_limits;  // per component: |state| bound and why (may be empty)
  // The body of a kinematic tree in joint coordinates this node belongs to,
  // and its parent body ("" for ground); empty for nodes outside such a tree.
  std::string tree_node, tree_parent;
  bool generated = false;  // by the multibody layer: its equations are not read for units
};

struct Bond {
  std::string name;   // user's name or "b<number>"
  int number = 0;     // 1-based, in declaration order (what dumps and reports show)
  SourceLoc loc;
  int from = -1, to = -1;            // node indices; power flows from -> to
  int dim = 1;
  std::vector<int> effort_vars;      // one per component
  std::vector<int> flow_vars;
  // Causality (set by the causality pass): the node that computes the effort.
  int effort_setter = -1;
};

/// Discrete: a value the model holds between events and only the runtime
/// changes, there (a contact's mode, its approach speed).
enum class VarKind { Effort, Flow, State, Derivative, Signal, Auxiliary, Discrete };

struct Variable {
  std::string name;   // model terms: "armature_l.p", "b3.e[2]", "der(rotor.p)"
  VarKind kind = VarKind::Auxiliary;
  SourceLoc loc;
  int of = -1;        // Derivative: the state variable id; Effort/Flow: the bond index
};

struct Parameter {
  std::string name;    // full path ("m1.V")
  SourceLoc loc;
  Expr value;          // in terms of earlier parameters (ordered: dependencies first)
  bool literal = false;
  double literal_value = 0.0;
  std::optional<DeclaredUnit> unit;  // as the model states it (`param k = 3e4 {N/m}`)
  bool generated = false;            // by the multibody layer: its value is not read for units
  std::optional<units::Dimension> stated;  // the dimension the multibody layer states of it (a body's mass: kg)
  /// Its dimension as the units pass found it (declared, stated or
  /// inferred: units::record_dimensions); nullopt where nothing fixes it,
  /// or the check is off. The simulator lists it (--list-parameters).
  std::optional<units::Dimension> dimension;
};

struct Signal {
  std::string name;
  SourceLoc loc;
  int var = -1;
  Expr value;
  Expr rate;  // d/dt of the signal in closed form (a body's rotation: R skew(omega)), or null: the chain rule
  std::optional<DeclaredUnit> unit;
  bool generated = false;  // a quantity of the multibody layer's (`b.position`)
};

struct Output {
  std::string name;    // CSV column ("omega", or "v[2]" for vector outputs)
  SourceLoc loc;
  Expr value;
  std::optional<DeclaredUnit> unit;
  /// Its dimension as the units pass found it (declared or inferred:
  /// units::record_dimensions); nullopt where nothing fixes it, or the
  /// check is off. The CSV header shows it (`omega [rad/s]`).
  std::optional<units::Dimension> dimension;
};

/// A drawn body (ir/drawing.hpp): where it is, as expressions over the
/// unknowns, for mbgrt::Model::body_poses.
struct DrawnBody {
  std::shared_ptr<const Drawing> drawing;
  SourceLoc loc;
  std::vector<Expr> pose;   // origin (3, world) then the rotation body -> world (9, row-major)
  std::vector<Expr> modes;  // a flexible body's modal coordinates
  /// Calls f on every expression: the pose's, then the modes'.
  template <class F>
  void for_each_expr(F&& f) {
    for (Expr& e : pose) f(e);
    for (Expr& e : modes) f(e);
  }
  template <class F>
  void for_each_expr(F&& f) const {
    for (const Expr& e : pose) f(e);
    for (const Expr& e : modes) f(e);
  }
};

/// A dimension the multibody layer states for a value the user wrote
/// (ExpandedUnitCheck), lowered: every entry must have it.
struct UnitCheck {
  std::vector<Expr> items;
  units::Dimension dimension;
  SourceLoc loc;
  std::string what;
  bool quantity = false;  // ExpandedUnitCheck::quantity
};

struct SimSettings {
  std::optional<double> t_end, interval, rtol, atol, step, rho_inf, accuracy;
  std::optional<std::string> solver;
  SourceLoc solver_loc;  // of the solver's name, when given
  // The command-line option that chose the model's form (`--constraints
  // lagrange`), if one did: a solver the block names that cannot integrate
  // that form gives way to one that can (the block is a default).
  std::optional<std::string> form_option;
};

/// The `simulate { ... }` block's settings, declared once, in the order the
/// language reference lists them: a number's (where its value goes, its
/// dimension, its range), or the solver's, a word (no slot).
struct SimSetting {
  const char* name;
  std::optional<double> SimSettings::*slot;
  std::optional<units::Dimension> dimension;
  bool fraction = false;         ///< from 0 to 1 (else positive)
  const char* meaning = nullptr;  ///< what the number is, for a value out of its range
};
inline const std::vector<SimSetting>& sim_settings() {
  static const std::vector<SimSetting> all = {
      {"t_end", &SimSettings::t_end, units::dim::time()},
      {"interval", &SimSettings::interval, units::dim::time()},
      {"solver", nullptr, std::nullopt},
      {"rtol", &SimSettings::rtol, units::Dimension::none()},
      {"atol", &SimSettings::atol, std::nullopt},  // in each state's own unit
      {"step", &SimSettings::step, units::dim::time()},
      {"rho_inf", &SimSettings::rho_inf, units::Dimension::none(), true,
       "generalized_alpha's spectral radius at an infinite step: 0 damps the modes far above 1/step out at once, 1 "
       "damps none"},
      {"accuracy", &SimSettings::accuracy, units::Dimension::none()},
  };
  return all;
}

struct BondGraph {
  std::string model_name;
  std::string source_file;
  std::vector<Parameter> params;
  std::vector<GraphNode> nodes;
  std::vector<Bond> bonds;
  std::vector<Variable> vars;
  std::vector<Signal> signals;
  std::vector<Output> outputs;
  std::vector<DrawnBody> drawings;
  std::vector<UnitCheck> unit_checks;
  SimSettings settings;

  int add_var(std::string name, VarKind kind, SourceLoc loc, int of = -1) {
    vars.push_back({std::move(name), kind, loc, of});
    return static_cast<int>(vars.size()) - 1;
  }
};

/// +1 if bond b's direction agrees with node n's sign convention for its own
/// flow: power into passive elements (I, C, R) and into port 1 of a two-port;
/// out of sources and out of port 2. -1 otherwise (the element's flow is -f).
int flow_sign(const BondGraph& g, int n, int b);

}  // namespace mbgc::ir
