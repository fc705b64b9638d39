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
    case AstExpr::Kind::Name: t->kind = Term::Kind::Ref, t->ref = {Ref::Kind::Name, -1, Quantity::value}; break;
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

std::optional<AstUnit> declared_unit(const std::optional<AstUnit>& after, const TermPtr& value) {
  if (after) return after;
  const Term* e = value.get();
  while (e && e->kind == Term::Kind::Unary && !e->args.empty()) e = e->args[0].get();
  if (e && e->kind == Term::Kind::Number && e->unit) return e->unit;
  return std::nullopt;
}

bool reads_a_ref(const Term& e) {
  if (e.kind == Term::Kind::Ref) return true;
  for (const TermPtr& a : e.args)
    if (reads_a_ref(*a)) return true;
  return false;
}

}  // namespace mbgc::ir
