// ir/resolved.hpp — the model after name resolution: components flattened
// into dotted names ("m1.rotor"), parameters ordered and lowered, bond ends
// bound to nodes. Expressions that may refer to variables (element laws,
// signals, outputs) stay as AST with the scope to resolve them in: only the
// graph pass knows the variables.
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
#include "ir/value.hpp"

namespace mbgc::ir {

/// A naming scope: the top level (prefix "") or one component instance ("m1.").
struct Scope {
  std::string prefix;
  std::string component;  // component name (empty at top level)
};

struct ResolvedNode {
  NodeKind kind = NodeKind::Zero;
  std::string name;      // full path
  SourceLoc loc;
  SourceLoc kind_loc;
  int scope = 0;
  std::optional<ExpandedElement> element;  // elements: the declaration
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
  std::string name;      // may be empty
  SourceLoc loc;
  ResolvedEnd from, to;
  std::optional<int> dim;
  SourceLoc dim_loc;
};

struct ResolvedExpr {
  std::string name;      // full path of the signal/output
  SourceLoc loc;
  AstExprPtr expr;
  int scope = 0;
  AstExprPtr rate;       // a signal's closed-form time derivative, if the multibody layer gave one
  std::optional<DeclaredUnit> unit;  // as declared: `output w = j.rate {rad/s}`
  bool generated = false;            // a signal of the multibody layer's
};

/// A body the multibody layer draws (ExpandedOutput::drawing).
struct ResolvedDrawing {
  std::shared_ptr<const Drawing> drawing;
  SourceLoc loc;
  AstExprPtr pose, modes;  // hcat(R, p); the modal coordinates (may be null)
  int scope = 0;
};

struct ResolvedModel {
  std::string model_name;
  std::string source_file;
  std::vector<Scope> scopes;               // scopes[0] is the top level
  std::vector<Parameter> params;           // scalar parameters, dependencies first
  std::unordered_map<std::string, Value> param_values;  // full name -> value over Param leaves
  std::vector<ResolvedNode> nodes;
  std::unordered_map<std::string, int> node_index;   // full name -> nodes index
  std::vector<ResolvedBond> bonds;
  std::vector<ResolvedExpr> signals;
  std::vector<ResolvedExpr> outputs;
  std::vector<ResolvedDrawing> drawings;
  std::vector<ExpandedUnitCheck> unit_checks;  // at the top level
  SimSettings settings;
  std::vector<std::shared_ptr<const AstComponent>> components;  // keeps ASTs alive
};

}  // namespace mbgc::ir
