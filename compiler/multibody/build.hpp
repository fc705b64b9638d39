// multibody/build.hpp — building the terms (ir/term.hpp) of the multibond-graph
// fragments the multibody layer writes (every one carries the location of
// the declaration it came from, so generated code points back at the model).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ir/ast.hpp"
#include "ir/term.hpp"
#include "ir/element_settings.hpp"
#include "ir/expanded.hpp"
#include "multibody/symbols.hpp"

namespace mbgc::multibody::detail {

using E = ir::TermPtr;

// ---- building terms (all carry the location of the declaration) --------------------
class Build {
 public:
  /// Terms at `loc`, their references given ids by `symbols`.
  Build(ir::SourceLoc loc, SymbolIds& symbols) : loc_(loc), symbols_(&symbols) {}
  E num(double v) const { return make(ir::Term::Kind::Number, [&](ir::Term& e) { e.number = v; }); }
  /// What the layer wrote under `s`, or one of its variables (a name is
  /// never built here: symbols.hpp).
  E ref(const Sym& s) const {
    return make(ir::Term::Kind::Ref, [&](ir::Term& e) {
      e.name = s.str();  // (shown in dumps)
      switch (s.kind()) {
        case Sym::Kind::Own: e.ref = {ir::Ref::Kind::Own, -1, s.quantity()}; break;
        case Sym::Kind::Pi: e.ref = {ir::Ref::Kind::Pi, -1, ir::Quantity::value}; break;
        case Sym::Kind::Entity: e.ref = {ir::Ref::Kind::Symbol, symbols_->id(s.owner()), s.quantity()}; break;
      }
    });
  }
  /// The id of the entity `s` (what its declaration carries).
  int id(const Sym& s) const { return symbols_->id(s.owner()); }
  /// A bond's end at what `s` is (an element, a junction, a two-port's port).
  ir::ExpandedEnd end(const Sym& s) const { return ir::ExpandedEnd{{s.str(), loc_}, id(s), s.end_port()}; }
  SymbolIds& symbols() const { return *symbols_; }
  E op(char o, E a, E b) const {
    return make(ir::Term::Kind::Binary, [&](ir::Term& e) { e.op = o; e.args = {std::move(a), std::move(b)}; });
  }
  E neg(E a) const { return make(ir::Term::Kind::Unary, [&](ir::Term& e) { e.op = '-'; e.args = {std::move(a)}; }); }
  E call(const std::string& fn, std::vector<E> args) const {
    return make(ir::Term::Kind::Call, [&](ir::Term& e) { e.name = fn; e.args = std::move(args); });
  }
  E list(std::vector<E> items) const { return make(ir::Term::Kind::List, [&](ir::Term& e) { e.args = std::move(items); }); }
  E vec(double x, double y, double z) const { return list({num(x), num(y), num(z)}); }
  E at(E a, int i) const { return make(ir::Term::Kind::Index, [&](ir::Term& e) { e.args = {std::move(a), num(i)}; }); }
  E dot(E a, E b) const { return call("dot", {std::move(a), std::move(b)}); }
  /// Setting `s`'s default value (settings.hpp), a number or a list of them.
  E default_of(const Setting& s) const {
    const std::vector<double> x = s.by_default.numbers();
    if (x.empty()) throw std::logic_error(fmt::format("setting `{}` has no numeric default", s.name));
    if (s.by_default.value[0] != '[') return num(x[0]);
    std::vector<E> items;
    for (double v : x) items.push_back(num(v));
    return list(std::move(items));
  }
  const ir::SourceLoc& loc() const { return loc_; }

 private:
  template <class F>
  E make(ir::Term::Kind k, F fill) const {
    auto e = std::make_shared<ir::Term>();
    e->kind = k;
    e->loc = loc_;
    fill(*e);
    return e;
  }
  ir::SourceLoc loc_;
  SymbolIds* symbols_;
};

/// m[r, c] (1-based), for a matrix-valued expression.
inline E idx2(const Build& B, E m, int r, int c) {
  auto e = std::make_shared<ir::Term>();
  e->kind = ir::Term::Kind::Index;
  e->loc = B.loc();
  e->args = {std::move(m), B.num(r), B.num(c)};
  return e;
}

/// A setting of a generated element (ir::element_setting: `q0`, `f0`, a law `e`, ...).
inline ir::TermAttr kv(const ir::ElementSetting& s, E value, const ir::SourceLoc& loc) { return ir::TermAttr{s.key, loc, std::move(value)}; }

/// What the user wrote, as a term (its names bound later, by resolve).
inline E term(const ir::AstExprPtr& e) { return ir::to_term(e); }

}  // namespace mbgc::multibody::detail
