// ir/resolved.hpp — the model after name resolution: components flattened
// into dotted names ("m1.rotor"), parameters ordered and lowered, bond ends
// bound to nodes, and every name in an element law, a signal, an output or
// a drawing bound to what it stands for (ir/term.hpp). The graph pass makes
// the variables and lowers the terms over them; it reads no name.
#pragma once

#include <map>
#include <unordered_map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/expanded.hpp"
#include "ir/graph.hpp"
#include "ir/term.hpp"
#include "ir/value.hpp"

namespace mbgc::ir {

/// A naming scope: the top level (prefix "") or one component instance ("m1.").
struct Scope {
  std::string prefix;
  std::string component;  // component name (empty at top level)
};

using BoundConstraintLaw = ConstraintLaw;  // its terms bound

/// The quantities a one-port element has, for a "has no quantity" hint.
inline const char* element_quantities(NodeKind k) {
  return k == NodeKind::I   ? "an I element has e, f and its momentum p"
         : k == NodeKind::C ? "a C element has e, f and its displacement q"
                            : "this element has e and f";
}

/// An element's declaration with its expressions bound: its value, the
/// settings in its braces and, for a CN the multibody layer wrote, its law.
struct BoundElement {
  std::string kind;  // as written: Se Sf I C R TF GY MTF MGY CN
  TermPtr value;     // may be null (a law in the braces instead)
  /// In the order written; a key the element does not take keeps a null value (the graph pass reports it).
  std::vector<TermAttr> attrs;
  std::optional<BoundConstraintLaw> constraint;
  bool configuration_dependent = false;                         // ExpandedElement's
  std::vector<std::pair<double, std::string>> state_limits;     // ExpandedElement's
};

struct ResolvedNode {
  NodeKind kind = NodeKind::Zero;
  std::string name;      // full path
  SourceLoc loc;
  SourceLoc kind_loc;
  std::optional<BoundElement> element;  // elements: the declaration
  std::optional<int> dim;                // junctions: declared [n]
  SourceLoc dim_loc;
  TreeTag tree;                          // the kinematic tree's body it belongs to (ExpandedElement::tree)
  bool generated = false;                // by the multibody layer (ExpandedElement::generated)
};

struct ResolvedEnd {
  int node = -1;
  int port = 0;          // 0: one-port or junction; 1/2: two-port side
  SourceLoc loc;
};

struct ResolvedBond {
  std::string name;      // as declared; may be empty
  std::string label;     // its name, else b<number> (b<number>_2, ... past a name taken)
  SourceLoc loc;
  ResolvedEnd from, to;
  std::optional<int> dim;
  SourceLoc dim_loc;
};

struct ResolvedExpr {
  std::string name;      // full path of the signal/output
  SourceLoc loc;
  TermPtr expr;
  TermPtr rate;          // a signal's closed-form time derivative, if the multibody layer gave one
  std::optional<DeclaredUnit> unit;  // as declared: `output w = j.rate {rad/s}`
  bool generated = false;            // a signal of the multibody layer's
};

/// A body the multibody layer draws (ExpandedOutput::drawing).
struct ResolvedDrawing {
  std::shared_ptr<const Drawing> drawing;
  SourceLoc loc;
  TermPtr pose, modes;  // hcat(R, p); the modal coordinates (may be null)
};

/// ExpandedUnitCheck with its value bound (null where it did not bind: the
/// value was reported where the multibody layer read it).
struct BoundUnitCheck {
  TermPtr value;
  units::Dimension dimension;
  SourceLoc loc;
  std::string what;
  bool quantity = false;
};

struct ResolvedModel {
  std::string model_name;
  std::string source_file;
  std::vector<Scope> scopes;               // scopes[0] is the top level
  std::vector<Parameter> params;           // scalar parameters, dependencies first
  std::vector<Value> param_values;         // each declared parameter's value over Param leaves (Ref::Param)
  std::unordered_map<std::string, int> param_index;  // full name -> param_values index (what names bind to)
  std::vector<ResolvedNode> nodes;
  std::unordered_map<std::string, int> node_index;   // full name -> nodes index
  std::vector<ResolvedBond> bonds;
  std::vector<ResolvedExpr> signals;
  std::vector<ResolvedExpr> outputs;
  std::vector<ResolvedDrawing> drawings;
  std::vector<BoundUnitCheck> unit_checks;  // at the top level
  SimSettings settings;
  std::vector<std::shared_ptr<const AstComponent>> components;  // keeps ASTs alive
};

}  // namespace mbgc::ir
