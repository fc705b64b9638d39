// ir/ast.hpp — the syntax tree of a .mbg file, as written (no names resolved).
// Produced by parse, consumed by unroll and the multibody expansion, which
// write ir/expanded.hpp; no later pass sets a field here. Every node keeps its
// SourceLoc.
#pragma once

#include <memory>
#include <optional>
#include <type_traits>
#include <string>
#include <variant>
#include <vector>

#include "ir/declared_unit.hpp"
#include "ir/diagnostics.hpp"
#include "ir/drawing.hpp"

namespace mbgc::ir {

/// A unit in braces, `{N/m}`, as written (its text) and what it means.
using AstUnit = DeclaredUnit;

struct AstExpr;
using AstExprPtr = std::shared_ptr<const AstExpr>;

struct AstExpr {
  enum class Kind {
    Number,  // number
    Name,    // name: a dotted path, e.g. `rotor.p`, `m1.loop.f`, `t`, `pi`
    Unary,   // op ('-' or '+') args[0]
    Binary,  // args[0] op args[1], op in + - * / ^
    Call,    // name(args...)
    Index,   // args[0] [ args[1] (, args[2]) ]   1-based
    List,    // [ args... ]  (a vector; a list of lists is a matrix)
    String,  // "text" in name: only a file name, as in flexible = modal("arm.mbm")
  };
  Kind kind = Kind::Number;
  SourceLoc loc;
  double number = 0.0;             // in SI when the literal has a unit
  std::optional<AstUnit> unit;     // a literal's: `30 {deg}`
  double written = 0.0;            // the literal as typed, when it has a unit
  std::string name;
  char op = 0;
  std::vector<AstExprPtr> args;
};

/// `key = value` inside an element's { } or the simulate { } block.
struct AstAttr {
  std::string key;
  SourceLoc loc;
  AstExprPtr value;
};

/// An end of a bond: `name` or `name.port` (dotted path, resolved later).
struct AstEndpoint {
  std::string path;
  SourceLoc loc;
};

struct AstModel { std::string name; SourceLoc loc; };
struct AstImport { std::string path; SourceLoc loc; };
/// `param name = expr [{unit}]`.
struct AstParam {
  std::string name;
  SourceLoc loc;
  AstExprPtr value;
  std::optional<AstUnit> unit;  // after the value: `param k = m*g/x0 {N/m}`
};
/// `signal NAME = value [{unit}]`.
struct AstSignal {
  std::string name;
  SourceLoc loc;
  AstExprPtr value;
  std::optional<AstUnit> unit;
};
/// `output NAME = value [{unit}]`.
struct AstOutput {
  std::string name;
  SourceLoc loc;
  AstExprPtr value;
  std::optional<AstUnit> unit;
};

/// The unit a declaration states: the one after its value, else its value's
/// when that is a literal (`param m = 1400 {kg}`, `param x0 = -3 {mm}`).
/// `Ptr`: an AST expression's or a term's (ir/term.hpp), which share these kinds.
template <class Ptr>
std::optional<AstUnit> declared_unit(const std::optional<AstUnit>& after, const Ptr& value) {
  if (after) return after;
  const auto* e = value.get();
  using Kind = typename std::remove_cvref_t<decltype(*e)>::Kind;
  while (e && e->kind == Kind::Unary && !e->args.empty()) e = e->args[0].get();
  if (e && e->kind == Kind::Number && e->unit) return e->unit;
  return std::nullopt;
}

/// `Se supply = expr`, `R fr { e = c*f^2 }`, `C k = 1/k_s { q0 = 0.1 }`.
struct AstElement {
  std::string kind;   // Se Sf I C R TF GY MTF MGY
  SourceLoc kind_loc;
  std::string name;
  SourceLoc loc;      // of the name
  AstExprPtr value;   // may be null (nonlinear law given in attrs)
  std::vector<AstAttr> attrs;
};

/// `1 loop [n] : a, b -> c, d` — a junction and, optionally, the bonds into
/// (left of ->) and out of (right of ->) it; their ends are `End`s (the
/// expanded program's have their own: ir/expanded.hpp).
template <class End>
struct JunctionForm {
  char type = '0';
  SourceLoc kind_loc;
  std::string name;
  SourceLoc loc;
  std::optional<int> dim;
  SourceLoc dim_loc;
  std::vector<End> inputs;
  std::vector<End> outputs;
};
using AstJunction = JunctionForm<AstEndpoint>;

/// `bond [name :] from -> to [n]`: power flows from `from` to `to`.
template <class End>
struct BondForm {
  std::string name;  // may be empty
  SourceLoc loc;     // of the `bond` keyword
  End from;
  End to;
  std::optional<int> dim;
  SourceLoc dim_loc;
};
using AstBond = BondForm<AstEndpoint>;

struct AstSimulate { SourceLoc loc; std::vector<AstAttr> settings; };
/// `scene name { outputs = [a, b]; modes = 2 }`: the outputs a run needs and
/// parameters it fixes (as `mbgc --set`). Chosen with `mbgc --scene name`;
/// the driver takes scenes out of the program before elaboration.
struct AstScene { std::string name; SourceLoc loc; std::vector<AstAttr> attrs; };

struct AstComponent;
/// `instance m1 = dc_motor(shaft = speed, V = 48)`
struct AstInstance {
  std::string name;
  SourceLoc loc;
  std::string component;
  SourceLoc component_loc;
  std::vector<AstAttr> args;  // port = endpoint (a Name expr) or param = expr
};

// ---- the multibody layer (expanded into the statements above by elaborate) ----

/// `point tip = [0.5, 0, 0]` inside a body (or ground) block: a named point,
/// in body-frame coordinates.
struct AstPoint { std::string name; SourceLoc loc; AstExprPtr value; };

/// `for i in 1..N { point p{i} = [...] }` inside a body or ground block: the
/// points repeated for i = from..to (loops may nest). Unroll flattens it into
/// the block's points, at `position` (the number of the enclosing list's
/// points declared before the loop), so later passes never see one.
struct AstPointFor {
  std::string var;
  SourceLoc loc;          // of `for`
  AstExprPtr from, to;
  std::size_t position = 0;
  std::vector<AstPoint> points;
  std::vector<std::shared_ptr<AstPointFor>> loops;
};

/// `body link { mass = 1; inertia = diag(...); com = [...]; point tip = [...] }`,
/// and `ground { point pivot = [...] }` (name "ground", no attrs): a rigid body.
/// Names inside `for` loops may carry interpolations, e.g. "link{i}", "tip{i}".
struct AstBody {
  std::string name;
  SourceLoc loc;          // of the name
  SourceLoc kind_loc;     // of `body` / `ground`
  std::vector<AstAttr> attrs;
  std::vector<AstPoint> points;
  std::vector<std::shared_ptr<AstPointFor>> loops;  // empty after unroll
};

/// What connects two bodies: a joint, a force element, a contact or a tyre.
/// They share one statement shape (`keyword name[ type](a, b) { settings }`)
/// and one namespace.
enum class Connector { Joint, Force, Contact, Tyre };
/// "joint", "force element", "contact", "tyre"
inline const char* connector_noun(Connector c) {
  switch (c) {
    case Connector::Joint: return "joint";
    case Connector::Force: return "force element";
    case Connector::Contact: return "contact";
    case Connector::Tyre: return "tyre";
  }
  return "joint";
}
/// The statement's keyword: "joint", "force", "contact", "tyre"
inline const char* connector_keyword(Connector c) { return c == Connector::Force ? "force" : connector_noun(c); }

/// `joint j1 revolute(ground.pivot, crank.a) { axis = [0, 0, 1]; q0 = 0.3 }`:
/// a joint between a point on body a and a point on body b (an endpoint is
/// `body.point`, `body` (its frame origin) or `ground`/`ground.point`);
/// `force f(a, b) { ... }` and `contact c(a, b) { ... }` have the same shape.
struct AstJoint {
  Connector connector = Connector::Joint;
  std::string name;
  SourceLoc loc;          // of the name
  SourceLoc kind_loc;     // of `joint` / `force` / `contact`
  std::string type;       // joints: revolute, spherical, ... (empty for forces and contacts)
  SourceLoc type_loc;
  AstEndpoint a, b;
  std::vector<AstAttr> attrs;
};

/// A model-wide setting statement: `gravity = [0, -9.81, 0]`,
/// `constraints = lagrange` (value is then a Name expression).
struct AstSetting { std::string key; SourceLoc loc; AstExprPtr value; };

struct AstFor;

using AstStmt = std::variant<AstModel, AstImport, AstParam, AstSignal, AstOutput, AstElement,
                             AstJunction, AstBond, AstSimulate, AstScene, AstInstance,
                             std::shared_ptr<AstComponent>, AstBody, AstJoint, AstSetting,
                             std::shared_ptr<AstFor>>;

/// `for i in 1..N { statements }`: the statements repeated for i = from..to
/// (integers, both ends included; bounds are parameter expressions known at
/// compile time). Inside, a name may interpolate `{expr}` (e.g. `link{i-1}.tip`,
/// `output q{i} = ...`): the text keeps "{expr}" verbatim (whitespace removed)
/// and elaborate substitutes the value.
struct AstFor {
  std::string var;
  SourceLoc loc;          // of `for`
  AstExprPtr from, to;
  std::vector<AstStmt> body;
};

/// `component name(port a, port b, param V = 60) { statements }`
struct AstComponent {
  std::string name;
  SourceLoc loc;
  std::vector<AstEndpoint> ports;  // port names
  std::vector<AstParam> params;    // parameters with defaults
  std::vector<AstStmt> body;
};

struct AstProgram {
  std::vector<AstStmt> stmts;  // imports already spliced in by the driver
};

}  // namespace mbgc::ir
