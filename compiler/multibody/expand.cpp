#include "multibody/expand.hpp"

#include "multibody/collect.hpp"
#include "multibody/expander.hpp"
#include "multibody/quantities.hpp"
#include "multibody/rewrite.hpp"
#include "multibody/rotors.hpp"
#include "multibody/spanning_tree.hpp"
#include "multibody/units.hpp"

#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody {
namespace detail {

std::vector<ir::ExpandedStmt> Expander::run() {
  if (m_.gravity) property(Build(m_.gravity_loc, symbols_), Sym::gravity(), term(m_.gravity));
  for (const auto& [p, v] : m_.bodies.at("ground").points) property(Build(v->loc, symbols_), Sym::ground_point(p), term(v));
  for (const std::string& name : m_.body_order) emit_body(m_.bodies.at(name));
  for (const Joint& j : m_.joints) emit_joint(j);
  place_bodies();
  define_quantities();
  draw_bodies();
  // a drive load may read the bodies' and joints' quantities, defined now (a force element's laws, rewritten as
  // it is written, also those of the force elements before it)
  for (std::size_t k : applied_) {
    auto& el = std::get<ir::ExpandedElement>(generated_[k]);
    el.value = rewrite_.expr(el.value);
  }
  for (const ForceElement& f : m_.forces) emit_force(f);
  for (const Contact& c : m_.contacts) emit_contact(c);
  for (const Tyre& t : m_.tyres) emit_tyre(t);
  return std::move(generated_);
}

// ---- 2. bodies -------------------------------------------------------------------------
void Expander::param(const Build& B, const Sym& name, E value) {
  quantities_.generated(name.str());
  generated_.push_back(ir::ExpandedParam{name.str(), B.loc(), std::move(value), std::nullopt, /*fold=*/false, true, name.dimension(), B.id(name)});
}

void Expander::property(const Build& B, const Sym& name, E value) {
  quantities_.generated(name.str());
  generated_.push_back(ir::ExpandedParam{name.str(), B.loc(), std::move(value), std::nullopt, /*fold=*/true, true, name.dimension(), B.id(name)});
}

void Expander::element(const Build& B, const std::string& kind, const Sym& name, E value, std::vector<TermAttr> attrs) {
  quantities_.generated(name.str());
  ir::ExpandedElement el;
  el.kind = kind;
  el.kind_loc = B.loc();
  el.name = name.str();
  el.loc = B.loc();
  el.value = std::move(value);
  el.attrs = std::move(attrs);
  el.tree = tree_tag_;
  el.generated = true;
  el.symbol = B.id(name);
  generated_.push_back(std::move(el));
}

void Expander::constraint(const Build& B, const Sym& name, ir::ConstraintLaw law) {
  element(B, "CN", name, nullptr);
  std::get<ir::ExpandedElement>(generated_.back()).constraint = std::move(law);
}

void Expander::junction(const Build& B, char type, const Sym& name, int dim, const std::vector<Sym>& in, const std::vector<Sym>& out) {
  quantities_.generated(name.str());
  ir::ExpandedJunction j;
  j.type = type;
  j.kind_loc = B.loc();
  j.name = name.str();
  j.loc = B.loc();
  j.dim = dim;
  j.dim_loc = B.loc();
  for (const Sym& s : in) j.inputs.push_back(B.end(s));
  for (const Sym& s : out) j.outputs.push_back(B.end(s));
  j.tree = tree_tag_;
  j.generated = true;
  j.symbol = B.id(name);
  generated_.push_back(std::move(j));
}

void Expander::bond(const Build& B, const Sym& from, const Sym& to, std::optional<int> dim) {
  ir::ExpandedBond b;
  b.loc = B.loc();
  b.dim = dim;
  b.dim_loc = B.loc();
  b.from = B.end(from);
  b.to = B.end(to);
  generated_.push_back(std::move(b));
}

void Expander::signal(const Build& B, const Sym& name, E value, E rate) {
  quantities_.generated(name.str());
  generated_.push_back(ir::ExpandedSignal{name.str(), B.loc(), std::move(value), std::nullopt, std::move(rate), true, B.id(name)});
}

void Expander::junction_(const Build& B, const Sym& name, const std::vector<Sym>& in, const std::vector<Sym>& out) {
  junction(B, '1', name, 1, in, out);
}

void Expander::named_bond(const Build& B, const Sym& name, const Sym& from, const Sym& to) {
  bond(B, from, to);
  auto& b = std::get<ir::ExpandedBond>(generated_.back());
  b.name = name.str();
  b.symbol = B.id(name);
  quantities_.generated(name.str());
}

}  // namespace detail

ir::ExpandedProgram expand(const ir::AstProgram& program, ir::SourceManager& sources, ir::Diagnostics& diags,
                           const ExpandOptions& options) {
  using namespace detail;
  Model m = Collector(sources, diags, options).run(program);
  if (diags.has_errors()) return {};
  if (m.bodies.size() <= 1 && m.joints.empty() && m.forces.empty() && m.contacts.empty() && m.tyres.empty() && !m.gravity)
    return ir::as_expanded(program);  // nothing multibody here
  plan_tree(m, diags, options.strategy_report);
  if (diags.has_errors()) return {};
  if (options.rotors) find_rotors(m, options.strategy_report);
  Quantities quantities;
  QuantityRewriter rewrite(quantities, m, diags);
  SymbolIds symbols;
  std::vector<ir::ExpandedStmt> generated = Expander(m, quantities, rewrite, symbols, diags).run();
  ir::ExpandedProgram out;
  out.stmts = rewrite_user_statements(program, rewrite);  // the user's statements first, then the layer's
  for (ir::ExpandedStmt& s : generated) out.stmts.push_back(std::move(s));
  if (!diags.has_errors()) out.unit_checks = state_units(m, quantities, rewrite.used(), symbols, diags);
  out.symbols = symbols.take();
  return out;
}

}  // namespace mbgc::multibody
