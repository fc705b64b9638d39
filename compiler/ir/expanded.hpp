// ir/expanded.hpp — the program after the multibody expansion, the input of
// resolve: plain bond-graph statements (parameters, signals, outputs,
// elements, junctions, bonds), those the user wrote and those the expansion
// derived from bodies, joints, forces, contacts and tyres, with what only the
// expansion knows of them. The AST (ir/ast.hpp) keeps what the parser read;
// the statements here hold terms (ir/term.hpp), not AST expressions: a
// user's statement passes through as its terms, its names unbound, with
// none of the extensions set.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "ir/ast.hpp"
#include "ir/drawing.hpp"
#include "ir/term.hpp"

namespace mbgc::ir {

/// A parameter. The expansion also writes the properties it derives (a
/// body's mass, centre, inertia and points, a joint's frames, the modal
/// integrals, gravity) with `fold` set: those are compile-time constants
/// wherever their value depends on literals only (a structural zero then
/// folds out of every equation), and run-time parameters (`--set`) where it
/// reads a `param`.
struct ExpandedParam {
  std::string name;
  SourceLoc loc;
  TermPtr value;
  std::optional<AstUnit> unit;  // after the value, as written
  bool fold = false;
  bool generated = false;  // by the multibody layer (a body's mass, a joint's frame), as ExpandedElement's
  /// What the multibody layer states of a generated one's dimension (a
  /// body's mass is kg), where it knows it: its value is not read for units.
  std::optional<units::Dimension> dimension = std::nullopt;
  int symbol = -1;  // the multibody layer's: its ExpandedProgram::symbols id (what refers to it)
};

/// A signal; `rate`, where the expansion knows its time derivative in closed
/// form (a body's rotation: R skew(omega)), is used for d/dt instead of the
/// chain rule through `value`.
struct ExpandedSignal {
  std::string name;
  SourceLoc loc;
  TermPtr value;
  std::optional<AstUnit> unit;
  TermPtr rate = nullptr;
  bool generated = false;  // by the multibody layer, not the user (as below)
  int symbol = -1;         // as ExpandedParam's
};

/// An output. The expansion writes one per body it draws (`drawing` set):
/// value is hcat(R, p), the pose of the point the drawing is measured from,
/// and `modes` a flexible body's modal coordinates.
struct ExpandedOutput {
  std::string name;
  SourceLoc loc;
  TermPtr value;
  std::optional<AstUnit> unit;
  std::shared_ptr<const Drawing> drawing = nullptr;
  TermPtr modes = nullptr;
};

/// A body of a kinematic tree in joint coordinates that an element or a
/// junction belongs to, and that body's parent in the tree ("" for ground):
/// reduce eliminates the tree's algebraic loop body by body, leaves first
/// (the articulated-body form). Empty outside such a tree.
struct TreeTag {
  std::string node, parent;
};

/// A constraintor's settings, typed: what holds its rows `g`, a penalty
/// (stiffness, damping), a Baumgarte rate (a cut joint's, a unilateral
/// contact's stabilisation) or a contact's law (restitution, and a compliant
/// one's stiffness and exponent, a unilateral one's friction). The
/// multibody layer writes its joints' and contacts' CNs with it; a user's CN
/// gives the same settings in braces, read into it by name (fields()).
/// `P` is what holds an expression: the AST's (here) or a bound term's
/// (ir/resolved.hpp).
template <class P>
struct ConstraintLawOf {
  P g, stiffness, damping, stabilisation, restitution, exponent, friction;

  struct Field {
    const char* key;  // as a CN's braces name it
    P ConstraintLawOf::*member;
    /// Its value where the law needs one and the CN does not give it (a
    /// unilateral contact's stabilisation, a compliant one's exponent).
    std::optional<double> default_value = std::nullopt;
  };
  /// Every setting, `g` first, in the order they are read and printed.
  static const std::vector<Field>& fields() {
    static const std::vector<Field> all = {
        {"g", &ConstraintLawOf::g},
        {"stiffness", &ConstraintLawOf::stiffness},
        {"damping", &ConstraintLawOf::damping},
        {"stabilisation", &ConstraintLawOf::stabilisation, 20},
        {"restitution", &ConstraintLawOf::restitution},
        {"exponent", &ConstraintLawOf::exponent, 1.5},
        {"friction", &ConstraintLawOf::friction},
    };
    return all;
  }
  /// The field of `member`.
  static const Field& field(P ConstraintLawOf::*member) {
    for (const Field& f : fields())
      if (f.member == member) return f;
    throw std::logic_error("ConstraintLaw::field: not a field");
  }
};
using ConstraintLaw = ConstraintLawOf<TermPtr>;

struct ExpandedElement {
  std::string kind;   // Se Sf I C R TF GY MTF MGY CN
  SourceLoc kind_loc;
  std::string name;
  SourceLoc loc;      // of the name
  TermPtr value;      // may be null (a law in the braces instead)
  std::vector<TermAttr> attrs;
  /// An I whose matrix depends on the configuration (a flexible body's mass
  /// matrix M(eta)), written only together with the efforts dT/deta that keep
  /// the field's energy balance; a user's I stays constant.
  bool configuration_dependent = false;
  /// Storage elements: per state component, the magnitude beyond which the
  /// model stops being valid, and why (a beam's modal coordinates: half its
  /// length of deflection). The simulator stops there with the reason.
  std::vector<std::pair<double, std::string>> state_limits;
  TreeTag tree;
  /// Made by the multibody layer (a body's inertia, a joint's rows), not
  /// written by the user: its equations are not read for units, which that
  /// layer's folded constants no longer carry.
  bool generated = false;
  /// A CN the multibody layer writes: its settings (a user's CN has them in
  /// `attrs`, by name).
  std::optional<ConstraintLaw> constraint = std::nullopt;
  int symbol = -1;  // as ExpandedParam's
};

/// An end of a bond: a path the user wrote (`name` or `name.port`), or
/// what the multibody layer wrote, by its symbol (and, at a two-port, which
/// port: 1 or 2); `path` then only shows it.
struct ExpandedEnd : AstEndpoint {
  int symbol = -1;
  int port = 0;
};

/// A junction and the bonds into and out of it.
struct ExpandedJunction : JunctionForm<ExpandedEnd> {
  TreeTag tree;
  bool generated = false;  // as ExpandedElement's
  int symbol = -1;         // as ExpandedParam's
};

/// A bond; the multibody layer's named ones have a symbol, as ExpandedParam's.
struct ExpandedBond : BondForm<ExpandedEnd> {
  int symbol = -1;
};

using ExpandedStmt = std::variant<AstModel, ExpandedParam, ExpandedSignal, ExpandedOutput, ExpandedElement,
                                  ExpandedJunction, ExpandedBond, AstSimulate, AstInstance, std::shared_ptr<AstComponent>>;

/// What the multibody layer states of a value the user wrote in one of its
/// statements (a joint's `torque` is N*m, a body's `mass` kg): units/check
/// holds the value, lowered, to it.
struct ExpandedUnitCheck {
  TermPtr value;              // quantities replaced by their definitions
  units::Dimension dimension;
  SourceLoc loc;              // of the setting
  std::string what;           // "the torque of joint `j1`"
  /// A quantity of the layer's own that the user's expressions read (`arm.position` is m):
  /// where they read it, it has this dimension (not a value the user wrote).
  bool quantity = false;
};

struct ExpandedProgram {
  std::vector<ExpandedStmt> stmts;
  /// What the multibody layer's terms refer to (Ref::Symbol's id): each
  /// symbol's name, which one of the statements above declares (its `symbol`).
  std::vector<std::string> symbols;
  std::vector<ExpandedUnitCheck> unit_checks;
};

/// A user's element as resolve reads it, none of the extensions set.
ExpandedElement as_expanded(const AstElement& e);

/// A user's statement as resolve reads it, none of the extensions set;
/// false for the statements the expansion consumes (bodies, joints,
/// settings), which have no such form, and for those resolve ignores
/// (imports, already spliced; scenes, already taken; loops, already unrolled).
bool as_expanded(const AstStmt& s, ExpandedStmt& out);

/// A program with nothing for the expansion to do, statement by statement
/// (as_expanded).
ExpandedProgram as_expanded(const AstProgram& program);

}  // namespace mbgc::ir
