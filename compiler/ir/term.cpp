#include "ir/term.hpp"

namespace mbgc::ir {

TermPtr to_term(const AstExprPtr& e) { return e ? to_term(*e) : nullptr; }

TermPtr to_term(const AstExpr& e) {
  auto t = std::make_shared<Term>();
  t->loc = e.loc;
  t->number = e.number;
  t->unit = e.unit;
  t->written = e.written;
  t->op = e.op;
  t->name = e.name;
  switch (e.kind) {
    case AstExpr::Kind::Number: t->kind = Term::Kind::Number; break;
    case AstExpr::Kind::Name:  // t and pi are the built-ins wherever they are written
      t->kind = Term::Kind::Ref;
      t->ref = {e.name == "t" ? Ref::Kind::Time : e.name == "pi" ? Ref::Kind::Pi : Ref::Kind::Name, -1, Quantity::value};
      break;
    case AstExpr::Kind::Unary: t->kind = Term::Kind::Unary; break;
    case AstExpr::Kind::Binary: t->kind = Term::Kind::Binary; break;
    case AstExpr::Kind::Call: t->kind = Term::Kind::Call; break;
    case AstExpr::Kind::Index: t->kind = Term::Kind::Index; break;
    case AstExpr::Kind::List: t->kind = Term::Kind::List; break;
    case AstExpr::Kind::String: t->kind = Term::Kind::String; break;
  }
  for (const AstExprPtr& a : e.args) t->args.push_back(to_term(*a));
  return t;
}


}  // namespace mbgc::ir
