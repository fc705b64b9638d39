// ir/term.hpp — the expressions of the middle of the compiler. A term has
// the AST's shape (numbers with their units, operators, calls, indexing,
// lists), but where the AST has a name, a term has a Ref. In the expanded
// program (ir/expanded.hpp) a ref is a name the user wrote (Name) or what
// the multibody layer wrote, by its symbol (Symbol); resolve binds both
// (sema/bind.hpp) to the parameter, signal, node or bond they stand for, by
// index into the resolved model, and which of its quantities. The graph
// pass reads only bound refs, never a name.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ir/ast.hpp"

namespace mbgc::ir {

/// A quantity a node or a bond has, as `name.e`, `tf.f2`, `contact.closed` read it.
enum class Quantity : std::uint8_t {
  value,   // a parameter's or a signal's value (not a node's quantity)
  e,       // effort
  f,       // flow
  p,       // an I's momentum
  q,       // a C's displacement (a free-rate Sf's state)
  e1,      // a two-port's effort and flow at port p1 and p2
  f1,
  e2,
  f2,
  closed,  // a contact CN: 1 while closed
  stick,   // ... 1 while its friction sticks
};

/// What a bound name stands for.
struct Ref {
  enum class Kind : std::uint8_t {
    Name,    // a name as the user wrote it (Term::name), not yet bound
    Symbol,  // what the multibody layer wrote: ExpandedProgram::symbols[id], and its quantity
    Time,    // t
    Pi,      // pi
    Param,   // a parameter: ResolvedModel::param_values[id]
    Signal,  // ResolvedModel::signals[id]
    Node,    // a quantity of ResolvedModel::nodes[id]
    Bond,    // the effort or flow of ResolvedModel::bonds[id]
    Own,     // inside an element's law: its own e, f, p or q
  };
  Kind kind = Kind::Time;
  int id = -1;
  Quantity quantity = Quantity::value;  // Symbol, Node, Bond, Own
};

struct Term;
using TermPtr = std::shared_ptr<const Term>;

struct Term {
  enum class Kind {
    Number,  // number, in SI; `unit` as written
    Ref,     // ref
    Unary,   // op ('-' or '+') args[0]
    Binary,  // args[0] op args[1]
    Call,    // name(args...)
    Index,   // args[0] [ args[1] (, args[2]) ]   1-based
    List,    // [ args... ]
    String,  // "name": not a value (lowering says so)
  };
  Kind kind = Kind::Number;
  SourceLoc loc;
  double number = 0.0;
  std::optional<AstUnit> unit;
  double written = 0.0;  // a number with a unit, as typed
  std::string name;  // a call's function, a string's text, a Name ref's name
  char op = 0;
  Ref ref;
  std::vector<TermPtr> args;
};

/// A setting in an element's braces (`e = c * f^2`, `q0 = x0`).
struct TermAttr {
  std::string key;
  SourceLoc loc;
  TermPtr value;
};

/// The AST expression as a term, its names unbound (Ref::Name; `t` and `pi`
/// the built-ins); null for null.
TermPtr to_term(const AstExprPtr& e);
TermPtr to_term(const AstExpr& e);

}  // namespace mbgc::ir
