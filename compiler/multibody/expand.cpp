#include "multibody/expand.hpp"

#include "multibody/collect.hpp"
#include "multibody/expander.hpp"
#include "multibody/spanning_tree.hpp"

#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody {
namespace detail {

ir::ExpandedProgram Expander::run(const AstProgram& in) {
  m_ = Collector(sources_, diags_, options_).run(in);
  if (diags_.has_errors()) return {};
  if (m_.bodies.size() <= 1 && m_.joints.empty() && m_.forces.empty() && m_.contacts.empty() && m_.tyres.empty() && !m_.gravity)
    return ir::as_expanded(in);  // nothing multibody here
  if (m_.gravity) property(Build(m_.gravity_loc), Sym::gravity(), m_.gravity);
  for (const auto& [p, v] : m_.bodies.at("ground").points) property(Build(v->loc), Sym::ground_point(p), v);
  plan_tree(m_, diags_, options_.strategy_report);
  if (diags_.has_errors()) return {};
  for (const std::string& name : m_.body_order) emit_body(m_.bodies.at(name));
  for (Joint& j : m_.joints) emit_joint(j);
  place_bodies();
  define_quantities();
  draw_bodies();
  for (std::size_t k : applied_) {
    auto& el = std::get<ir::ExpandedElement>(generated_[k]);
    el.value = rewrite_expr(el.value);
  }
  for (const ForceElement& f : m_.forces) emit_force(f);
  for (const Contact& c : m_.contacts) emit_contact(c);
  for (const Tyre& t : m_.tyres) emit_tyre(t);
  ir::ExpandedProgram out;
  for (const AstStmt& s : in.stmts)
    if (ir::ExpandedStmt e; ir::as_expanded(s, e)) out.stmts.push_back(rewrite_user(e));
  for (ir::ExpandedStmt& s : generated_) out.stmts.push_back(std::move(s));
  if (!diags_.has_errors()) state_units(out.unit_checks);
  return out;
}

// ---- 2. bodies -------------------------------------------------------------------------
void Expander::param(const Build& B, const Sym& name, E value) {
  quantities_.generated(name.str());
  generated_.push_back(ir::ExpandedParam{{name.str(), B.loc(), std::move(value), std::nullopt}, /*fold=*/false, true, name.dimension()});
}

void Expander::property(const Build& B, const Sym& name, E value) {
  quantities_.generated(name.str());
  generated_.push_back(ir::ExpandedParam{{name.str(), B.loc(), std::move(value), std::nullopt}, /*fold=*/true, true, name.dimension()});
}

void Expander::element(const Build& B, const std::string& kind, const Sym& name, E value, std::vector<AstAttr> attrs) {
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
  for (const Sym& s : in) j.inputs.push_back({s.str(), B.loc()});
  for (const Sym& s : out) j.outputs.push_back({s.str(), B.loc()});
  j.tree = tree_tag_;
  j.generated = true;
  generated_.push_back(std::move(j));
}

void Expander::bond(const Build& B, const Sym& from, const Sym& to, std::optional<int> dim) {
  AstBond b;
  b.loc = B.loc();
  b.dim = dim;
  b.dim_loc = B.loc();
  b.from = {from.str(), B.loc()};
  b.to = {to.str(), B.loc()};
  generated_.push_back(std::move(b));
}

void Expander::signal(const Build& B, const Sym& name, E value, E rate) {
  quantities_.generated(name.str());
  generated_.push_back(ir::ExpandedSignal{{name.str(), B.loc(), std::move(value), std::nullopt}, std::move(rate), true});
}

void Expander::junction_(const Build& B, const Sym& name, const std::vector<Sym>& in, const std::vector<Sym>& out) {
  junction(B, '1', name, 1, in, out);
}

void Expander::named_bond(const Build& B, const Sym& name, const Sym& from, const Sym& to) {
  bond(B, from, to);
  std::get<AstBond>(generated_.back()).name = name.str();
  quantities_.generated(name.str());
}

}  // namespace detail

ir::ExpandedProgram expand(const ir::AstProgram& program, ir::SourceManager& sources, ir::Diagnostics& diags,
                           const ExpandOptions& options) {
  detail::Expander x(sources, diags, options);
  return x.run(program);
}

}  // namespace mbgc::multibody
