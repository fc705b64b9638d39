#include "multibody/expand.hpp"

#include "multibody/expander.hpp"

#include <tuple>

#include <fmt/format.h>

namespace mbgc::multibody {
namespace detail {

ir::ExpandedProgram Expander::run(const AstProgram& in) {
  collect(in);
  if (diags_.has_errors()) return {};
  if (bodies_.size() <= 1 && joints_.empty() && forces_.empty() && contacts_.empty() && tyres_.empty() && !gravity_)
    return ir::as_expanded(in);  // nothing multibody here
  if (gravity_) property(Build(gravity_loc_), Sym::gravity(), gravity_);
  for (const auto& [p, v] : bodies_.at("ground").points) property(Build(v->loc), Sym::ground_point(p), v);
  find_tree();
  choose_strategy();
  check_coordinates();
  if (diags_.has_errors()) return {};
  for (const std::string& name : body_order_) emit_body(bodies_.at(name));
  for (Joint& j : joints_) emit_joint(j);
  place_bodies();
  define_quantities();
  draw_bodies();
  for (std::size_t k : applied_) {
    auto& el = std::get<ir::ExpandedElement>(generated_[k]);
    el.value = rewrite_expr(el.value);
  }
  for (const ForceElement& f : forces_) emit_force(f);
  for (const Contact& c : contacts_) emit_contact(c);
  for (const Tyre& t : tyres_) emit_tyre(t);
  ir::ExpandedProgram out;
  for (const AstStmt& s : in.stmts)
    if (ir::ExpandedStmt e; ir::as_expanded(s, e)) out.stmts.push_back(rewrite_user(e));
  for (ir::ExpandedStmt& s : generated_) out.stmts.push_back(std::move(s));
  if (!diags_.has_errors()) state_units(out.unit_checks);
  return out;
}

// ---- 2. bodies -------------------------------------------------------------------------
void Expander::param(const Build& B, const std::string& name, E value) {
  generated_names_.insert(name);
  generated_.push_back(ir::ExpandedParam{{name, B.loc(), std::move(value), std::nullopt}, /*fold=*/false, true});
}

void Expander::property(const Build& B, const std::string& name, E value) {
  generated_names_.insert(name);
  generated_.push_back(ir::ExpandedParam{{name, B.loc(), std::move(value), std::nullopt}, /*fold=*/true, true});
}

void Expander::element(const Build& B, const std::string& kind, const std::string& name, E value, std::vector<AstAttr> attrs) {
  generated_names_.insert(name);
  ir::ExpandedElement el;
  el.kind = kind;
  el.kind_loc = B.loc();
  el.name = name;
  el.loc = B.loc();
  el.value = std::move(value);
  el.attrs = std::move(attrs);
  el.tree = tree_tag_;
  el.generated = true;
  generated_.push_back(std::move(el));
}

void Expander::constraint(const Build& B, const std::string& name, ir::ConstraintLaw law) {
  element(B, "CN", name, nullptr);
  std::get<ir::ExpandedElement>(generated_.back()).constraint = std::move(law);
}

void Expander::junction(const Build& B, char type, const std::string& name, int dim, std::vector<std::string> in, std::vector<std::string> out) {
  generated_names_.insert(name);
  ir::ExpandedJunction j;
  j.type = type;
  j.kind_loc = B.loc();
  j.name = name;
  j.loc = B.loc();
  j.dim = dim;
  j.dim_loc = B.loc();
  for (auto& s : in) j.inputs.push_back({s, B.loc()});
  for (auto& s : out) j.outputs.push_back({s, B.loc()});
  j.tree = tree_tag_;
  j.generated = true;
  generated_.push_back(std::move(j));
}

void Expander::bond(const Build& B, const std::string& from, const std::string& to, std::optional<int> dim) {
  AstBond b;
  b.loc = B.loc();
  b.dim = dim;
  b.dim_loc = B.loc();
  b.from = {from, B.loc()};
  b.to = {to, B.loc()};
  generated_.push_back(std::move(b));
}

void Expander::signal(const Build& B, const std::string& name, E value, E rate) {
  generated_names_.insert(name);
  generated_.push_back(ir::ExpandedSignal{{name, B.loc(), std::move(value), std::nullopt}, std::move(rate), true});
}

/// A 1-junction with the given elements bonded into / out of it.
void Expander::junction_(const Build& B, const std::string& name, std::vector<std::string> in, std::vector<std::string> out) {
  junction(B, '1', name, 1, std::move(in), std::move(out));
}

void Expander::named_bond(const Build& B, const std::string& name, const std::string& from, const std::string& to) {
  bond(B, from, to);
  std::get<AstBond>(generated_.back()).name = name;
  generated_names_.insert(name);
}

}  // namespace detail

ir::ExpandedProgram expand(const ir::AstProgram& program, ir::SourceManager& sources, ir::Diagnostics& diags,
                           const ExpandOptions& options) {
  detail::Expander x(sources, diags, options);
  return x.run(program);
}

}  // namespace mbgc::multibody
