// sema/bind.hpp — binding the refs of a term (ir/term.hpp): each name
// replaced by what it stands for in its scope, each symbol of the multibody
// layer's by what declares it (SymbolTable: no name is looked up for it).
//
// Resolve binds every element law, signal, output and drawing with it once
// the model is flattened, its parameters evaluated and its bonds bound. A
// name is looked up as the graph reads it: inside an element's law its own
// e, f, p or q first; then a parameter (the component's, then the top
// level's); then a signal, a node's quantity (`rotor.p`, `tf.e2`) or a
// bond's (`b3.f`), the component's before the top level's. An unknown name,
// or a quantity its node does not have, is an error with a hint.
#pragma once

#include <string>
#include <unordered_map>

#include "ir/diagnostics.hpp"
#include "ir/resolved.hpp"
#include "ir/term.hpp"

namespace mbgc::sema {

/// What a symbol of the multibody layer's (ir::Ref::Symbol) declares, once
/// resolve has flattened the program.
struct SymbolTarget {
  enum class Kind { None, Param, Signal, Node, Bond };
  Kind kind = Kind::None;
  std::size_t index = 0;  // into the parameters (param_values), signals, nodes or bonds
};

/// The layer's symbols and what declares each. A ref to a symbol no
/// statement declares, or to a quantity its node has not, is the layer's
/// mistake, not the user's: an internal error (ir::InternalError).
struct SymbolTable {
  std::vector<std::string> names;  // ir::ExpandedProgram::symbols
  std::vector<SymbolTarget> targets;
  /// The parameter `ref` is.
  std::size_t param(const ir::Ref& ref) const;
  /// `ref` bound to what its symbol declares, in `model`.
  ir::Ref bind(const ir::Ref& ref, const ir::ResolvedModel& model) const;
};

/// Whether a node of kind `k` has quantity `q`.
bool has_quantity(ir::NodeKind k, ir::Quantity q);

/// The names an element's own law may use for its quantities.
struct OwnQuantities {
  bool any = false;   // e and f (a one-port's law)
  char state = 0;     // and 'p' (an I), 'q' (a C, a free-rate Sf), or none
};

class Binder {
 public:
  /// Over `model`: flattened, its parameters evaluated (param_index), its
  /// bonds labelled; `symbols`: what the multibody layer's symbols declare.
  Binder(const ir::ResolvedModel& model, const SymbolTable& symbols);

  /// `e` with its names bound in scope `scope` (an index into model.scopes);
  /// null after each unknown name was reported to `diags`.
  ir::TermPtr bind(const ir::Term& e, int scope, ir::Diagnostics& diags, OwnQuantities own = {}) const;

 private:
  bool name(const ir::Term& e, int scope, OwnQuantities own, ir::Ref& out, ir::Diagnostics& diags) const;
  /// `X.q` for a signal, node or bond named `full`: 1 bound, 0 not found, -1 reported.
  int quantity(const std::string& full, const ir::SourceLoc& loc, ir::Ref& out, ir::Diagnostics& diags) const;
  std::vector<std::string> known_names() const;

  const ir::ResolvedModel& m_;
  const SymbolTable& symbols_;
  std::unordered_map<std::string, int> signals_;  // full name -> signals index
  std::unordered_map<std::string, int> bonds_;    // label -> the first bond of that label
};

}  // namespace mbgc::sema
