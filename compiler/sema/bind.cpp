#include "sema/bind.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <memory>

namespace mbgc::sema {

using namespace mbgc::ir;

bool has_quantity(NodeKind k, Quantity q) {
  if (k == NodeKind::Zero) return q == Quantity::e;
  if (k == NodeKind::One) return q == Quantity::f;
  if (is_two_port(k)) return q == Quantity::e1 || q == Quantity::f1 || q == Quantity::e2 || q == Quantity::f2;
  switch (q) {
    case Quantity::e:
    case Quantity::f: return true;
    case Quantity::p: return k == NodeKind::I;
    case Quantity::q: return k == NodeKind::C;
    case Quantity::closed:
    case Quantity::stick: return k == NodeKind::CN;
    default: return false;
  }
}

std::size_t SymbolTable::param(const Ref& ref) const {
  const SymbolTarget& t = targets.at(static_cast<std::size_t>(ref.id));
  if (t.kind != SymbolTarget::Kind::Param)
    throw InternalError(fmt::format("the multibody layer reads `{}` as a parameter, which it did not declare as one",
                                    names.at(static_cast<std::size_t>(ref.id))));
  return t.index;
}

Ref SymbolTable::bind(const Ref& ref, const ResolvedModel& m) const {
  const SymbolTarget& t = targets.at(static_cast<std::size_t>(ref.id));
  const std::string& name = names.at(static_cast<std::size_t>(ref.id));
  const bool variable = ref.quantity != Quantity::value;
  switch (t.kind) {
    case SymbolTarget::Kind::Param:
      if (!variable) return {Ref::Kind::Param, static_cast<int>(t.index), Quantity::value};
      break;
    case SymbolTarget::Kind::Signal:
      if (!variable) return {Ref::Kind::Signal, static_cast<int>(t.index), Quantity::value};
      break;
    case SymbolTarget::Kind::Node:
      if (has_quantity(m.nodes[t.index].kind, ref.quantity)) return {Ref::Kind::Node, static_cast<int>(t.index), ref.quantity};
      break;
    case SymbolTarget::Kind::Bond:
      if (ref.quantity == Quantity::e || ref.quantity == Quantity::f)
        return {Ref::Kind::Bond, static_cast<int>(t.index), ref.quantity};
      break;
    case SymbolTarget::Kind::None:
      throw InternalError(fmt::format("the multibody layer refers to `{}`, which it did not declare", name));
  }
  throw InternalError(fmt::format("the multibody layer reads a quantity of `{}` that it does not have", name));
}

Binder::Binder(const ResolvedModel& model, const SymbolTable& symbols) : m_(model), symbols_(symbols) {
  for (std::size_t i = 0; i < m_.signals.size(); ++i) signals_.emplace(m_.signals[i].name, static_cast<int>(i));
  for (std::size_t b = 0; b < m_.bonds.size(); ++b) bonds_.emplace(m_.bonds[b].label, static_cast<int>(b));
}

TermPtr Binder::bind(const Term& e, int scope, Diagnostics& diags, OwnQuantities own) const {
  auto t = std::make_shared<Term>(e);
  bool ok = true;
  if (e.kind == Term::Kind::Ref && e.ref.kind == Ref::Kind::Name) ok = name(e, scope, own, t->ref, diags);
  if (e.kind == Term::Kind::Ref && e.ref.kind == Ref::Kind::Symbol) t->ref = symbols_.bind(e.ref, m_);
  for (TermPtr& a : t->args) {
    a = bind(*a, scope, diags, own);
    ok = ok && a != nullptr;
  }
  return ok ? t : nullptr;
}

bool Binder::name(const Term& e, int scope, OwnQuantities own, Ref& out, Diagnostics& diags) const {
  const std::string& name = e.name;
  if (own.any) {
    if (name == "e") return out = {Ref::Kind::Own, -1, Quantity::e}, true;
    if (name == "f") return out = {Ref::Kind::Own, -1, Quantity::f}, true;
    if (own.state && name.size() == 1 && name[0] == own.state)
      return out = {Ref::Kind::Own, -1, own.state == 'p' ? Quantity::p : Quantity::q}, true;
  }
  const std::string& prefix = m_.scopes[static_cast<std::size_t>(scope)].prefix;
  std::vector<std::string> tries;
  if (scope != 0) tries.push_back(prefix + name);
  tries.push_back(name);
  for (const std::string& full : tries)
    if (auto it = m_.param_index.find(full); it != m_.param_index.end())
      return out = {Ref::Kind::Param, it->second, Quantity::value}, true;
  for (const std::string& full : tries) {
    int found = quantity(full, e.loc, out, diags);
    if (found != 0) return found > 0;
  }
  std::vector<std::string> names = known_names();
  std::string near = closest_name(name, names);
  diags.error(e.loc, fmt::format("unknown name `{}`", name),
              near.empty() ? "refer to parameters, signals, t, or quantities like element.e, element.f, inertia.p"
                           : fmt::format("did you mean `{}`?", near));
  return false;
}

int Binder::quantity(const std::string& full, const SourceLoc& loc, Ref& out, Diagnostics& diags) const {
  if (auto it = signals_.find(full); it != signals_.end()) return out = {Ref::Kind::Signal, it->second, Quantity::value}, 1;
  auto dot = full.rfind('.');
  if (dot == std::string::npos) return 0;
  std::string stem = full.substr(0, dot), q = full.substr(dot + 1);
  auto report = [&](const std::string& message, const std::string& hint) {
    diags.error(loc, message, hint);
    return -1;
  };
  if (auto it = m_.node_index.find(stem); it != m_.node_index.end()) {
    const NodeKind kind = m_.nodes[static_cast<std::size_t>(it->second)].kind;
    auto bound = [&](Quantity quantity) { return out = {Ref::Kind::Node, it->second, quantity}, 1; };
    if (is_junction(kind)) {
      if (kind == NodeKind::Zero && q == "e") return bound(Quantity::e);
      if (kind == NodeKind::One && q == "f") return bound(Quantity::f);
      return report(fmt::format("{}-junction `{}` has no quantity `{}`", node_kind_name(kind), stem, q),
                    kind == NodeKind::Zero ? "a 0-junction has one common effort: use `.e`; for a flow, name a bond"
                                           : "a 1-junction has one common flow: use `.f`; for an effort, name a bond");
    }
    if (is_two_port(kind)) {
      if (q == "e1") return bound(Quantity::e1);
      if (q == "f1") return bound(Quantity::f1);
      if (q == "e2") return bound(Quantity::e2);
      if (q == "f2") return bound(Quantity::f2);
      return report(fmt::format("{} `{}` has no quantity `{}`", node_kind_name(kind), stem, q),
                    "two-ports have e1, f1 (port p1) and e2, f2 (port p2)");
    }
    if (q == "e") return bound(Quantity::e);
    if (q == "f") return bound(Quantity::f);
    if (q == "p" && kind == NodeKind::I) return bound(Quantity::p);
    if (q == "q" && kind == NodeKind::C) return bound(Quantity::q);
    if (kind == NodeKind::CN && q == "closed") return bound(Quantity::closed);  // a contact's (the graph checks)
    if (kind == NodeKind::CN && q == "stick") return bound(Quantity::stick);
    return report(fmt::format("{} `{}` has no quantity `{}`", node_kind_name(kind), stem, q), element_quantities(kind));
  }
  if (auto it = bonds_.find(stem); it != bonds_.end()) {
    if (q == "e") return out = {Ref::Kind::Bond, it->second, Quantity::e}, 1;
    if (q == "f") return out = {Ref::Kind::Bond, it->second, Quantity::f}, 1;
    return report(fmt::format("bond `{}` has no quantity `{}`", stem, q), "a bond has e and f");
  }
  return 0;
}

std::vector<std::string> Binder::known_names() const {
  std::vector<std::string> names;
  for (const auto& [n, i] : m_.param_index) names.push_back(n);
  for (const ResolvedExpr& s : m_.signals) names.push_back(s.name);
  for (const ResolvedNode& node : m_.nodes) {
    for (const char* q : {"e", "f", "p", "q"}) {
      if ((*q == 'p' && node.kind != NodeKind::I) || (*q == 'q' && node.kind != NodeKind::C)) continue;
      names.push_back(node.name + "." + q);
    }
  }
  std::sort(names.begin(), names.end());  // (from hash maps: the suggestion must not depend on their order)
  return names;
}

}  // namespace mbgc::sema
