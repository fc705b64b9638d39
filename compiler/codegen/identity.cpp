// codegen/identity.cpp — the model class's metadata methods.
#include "codegen/identity.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <unordered_set>

#include "codegen/names.hpp"
#include "units/unit.hpp"
#include "mbgrt/integrators.hpp"

namespace mbgc::codegen {
namespace {

using namespace mbgc::ir;

/// Bounds beyond which a state's model no longer holds (a beam's modal
/// coordinates): the runtime stops the run there and prints the reason.
void state_limits(CppClass& c, const ReducedSystem& s) {
  const BondGraph& g = s.graph;
  std::vector<std::string> bounds, reasons;
  for (std::size_t i = 0; i < s.states.size(); ++i) {
    const GraphNode& nd = g.nodes[static_cast<std::size_t>(s.states[i].node)];
    const auto& vars = nd.state_vars;
    auto k = static_cast<std::size_t>(std::find(vars.begin(), vars.end(), s.states[i].var) - vars.begin());
    if (k >= nd.state_limits.size()) continue;
    bounds.push_back(fmt::format("case {}: return {};", i, cpp_double(nd.state_limits[k].first)));
    reasons.push_back(fmt::format("case {}: return {};", i, cpp_string(nd.state_limits[k].second)));
  }
  if (bounds.empty()) return;
  CppFunction limit{"LIMITS: where a state's model stops being valid (the run stops there, with the reason).",
                    "double state_limit(std::size_t i) const override", {CppStmt::line("switch (i) {")}};
  CppFunction why{"", "std::string state_limit_reason(std::size_t i) const override", {CppStmt::line("switch (i) {")}};
  for (const auto& b : bounds) limit.body.push_back(CppStmt::line("  " + b));
  for (const auto& r : reasons) why.body.push_back(CppStmt::line("  " + r));
  limit.body.push_back(CppStmt::line("  default: return HUGE_VAL;"));
  why.body.push_back(CppStmt::line("  default: return {};"));
  limit.body.push_back(CppStmt::line("}"));
  why.body.push_back(CppStmt::line("}"));
  c.public_methods.push_back(limit);
  c.public_methods.push_back(why);
}

/// LAYOUT: what each unknown is, from the element that holds it: q of a C is
/// a position (a displacement), p of an I and an independent joint rate are
/// velocities; the DAE's algebraic unknowns are multipliers where a CN row
/// puts them.
void unknown_roles(CppClass& c, const ReducedSystem& s) {
  std::vector<std::string> roles;
  for (std::size_t i = 0; i < s.states.size(); ++i) roles.push_back(is_position_state(s, i) ? "position" : "velocity");
  for (int a : s.algebraic) {
    const char* role = "algebraic";
    for (const ConstraintRow& r : s.constraints) {
      if (r.multiplier == a) role = "multiplier";
      if (r.stabiliser == a) role = "stabiliser";
    }
    roles.push_back(role);
  }
  CppFunction f{"LAYOUT: what each unknown is (the runtime is told, not left to find out).",
                "mbgrt::UnknownRole unknown_role(std::size_t i) const override", {}};
  if (roles.empty()) {
    f.body.push_back(CppStmt::line("(void)i;"));
    f.body.push_back(CppStmt::line("return mbgrt::UnknownRole::unspecified;"));
    c.public_methods.push_back(f);
    return;
  }
  f.body.push_back(CppStmt::line("using R = mbgrt::UnknownRole;"));
  f.body.push_back(CppStmt::line("static const R kRoles[] = {"));
  for (std::size_t i = 0; i < roles.size(); i += 8) {
    std::vector<std::string> line;
    for (std::size_t k = i; k < std::min(roles.size(), i + 8); ++k) line.push_back("R::" + roles[k]);
    f.body.push_back(CppStmt::line(fmt::format("    {},", fmt::join(line, ", "))));
  }
  f.body.push_back(CppStmt::line("};"));
  f.body.push_back(CppStmt::line(fmt::format("return i < {} ? kRoles[i] : R::unspecified;", roles.size())));
  c.public_methods.push_back(f);
}

/// GROUP: the states of one multibond storage (a body's momentum, its
/// position) are one vector for the integrators' relative tolerance.
void unknown_groups(CppClass& c, const ReducedSystem& s) {
  std::map<int, std::size_t> first;  // storage node -> its first state
  std::vector<long> groups;
  bool any = false;
  for (std::size_t i = 0; i < s.states.size(); ++i) {
    const std::size_t g = first.try_emplace(s.states[i].node, i).first->second;
    any = any || g != i;
    groups.push_back(static_cast<long>(g));
  }
  if (!any) return;
  for (std::size_t j = 0; j < s.algebraic.size(); ++j) groups.push_back(static_cast<long>(s.states.size() + j));
  CppFunction f{"GROUPS: the first unknown of each unknown's vector (one storage's components), for the tolerances.",
                "std::size_t unknown_group(std::size_t i) const override", {}};
  static_table(f.body, "unsigned", "kGroups", groups);
  f.body.push_back(CppStmt::line(fmt::format("return i < {} ? kGroups[i] : i;", groups.size())));
  c.public_methods.push_back(f);
}

}  // namespace

/// "= FORMULA" of a computed parameter (sim --list-parameters prints it); a
/// long one (a joint frame from its axis) as the parameters it is computed from.
std::string computed_doc(const ir::Parameter& p, const ir::BondGraph& g) {
  // Every node prints at least one character: past 80 nodes, no need to print it.
  if (ir::size(p.value) <= 80) {
    std::string formula = to_string(p.value, names_for_dump(g));
    if (formula.size() <= 80) return "= " + formula;
  }
  std::unordered_set<int> ids;
  collect_params(p.value, ids);
  std::vector<int> order(ids.begin(), ids.end());
  std::sort(order.begin(), order.end());
  std::vector<std::string> from;
  for (int id : order) {
    const std::string& full = g.params[static_cast<std::size_t>(id)].name;
    std::string base = full.substr(0, full.find('['));  // link.axis_a[2] -> link.axis_a
    if (std::find(from.begin(), from.end(), base) == from.end()) from.push_back(base);
  }
  if (from.empty()) return "= a long constant expression";
  return fmt::format("= a function of {}", fmt::join(from, ", "));
}

ir::Namer names_for_dump(const ir::BondGraph& g) {
  ir::Namer n;
  n.var = [&g](int id) { return g.vars[static_cast<std::size_t>(id)].name; };
  n.param = [&g](int id) { return g.params[static_cast<std::size_t>(id)].name; };
  return n;
}

void add_identity_methods(CppClass& c, const ReducedSystem& s, const EmitOptions& opt, bool compact) {
  const BondGraph& g = s.graph;
  const std::size_t unknowns = s.states.size() + s.algebraic.size();
  c.public_methods.push_back({"", "const char* name() const override", {CppStmt::line(fmt::format("return {};", cpp_string(g.model_name)))}});
  c.public_methods.push_back({"", "const char* source_file() const override", {CppStmt::line(fmt::format("return {};", cpp_string(opt.source_display)))}});
  c.public_methods.push_back({"", "std::unique_ptr<mbgrt::Model> make_new() const override",
                              {CppStmt::line(fmt::format("return std::make_unique<{}>();", c.name))}});
  c.public_methods.push_back({"", "std::size_t size() const override", {CppStmt::line(fmt::format("return {};", unknowns))}});
  std::vector<std::string> unknown_names;
  for (const StateVar& st : s.states) unknown_names.push_back(cpp_string(g.vars[static_cast<std::size_t>(st.var)].name));
  for (int a : s.algebraic) unknown_names.push_back(cpp_string(g.vars[static_cast<std::size_t>(a)].name));
  CppFunction vn{"", "std::string variable_name(std::size_t i) const override", {}};
  if (unknown_names.empty()) {
    vn.body.push_back(CppStmt::line("(void)i;"));
    vn.body.push_back(CppStmt::line("return \"?\";"));
  } else {
    vn.body.push_back(CppStmt::line(fmt::format("static const char* const kNames[] = {{{}}};", fmt::join(unknown_names, ", "))));
    vn.body.push_back(CppStmt::line(fmt::format("return i < {} ? kNames[i] : \"?\";", unknown_names.size())));
  }
  c.public_methods.push_back(vn);
  unknown_roles(c, s);
  unknown_groups(c, s);
  state_limits(c, s);
  std::vector<std::string> outs;
  for (const Output& o : g.outputs) outs.push_back(cpp_string(o.name));
  c.public_methods.push_back({"", "std::vector<std::string> output_names() const override",
                              {CppStmt::line(fmt::format("return {{{}}};", fmt::join(outs, ", ")))}});
  // each output's unit for the CSV header (`omega [rad/s]`): as declared,
  // else the SI unit the units pass inferred (none for a plain number)
  std::vector<std::string> units;
  bool any_unit = false;
  for (const Output& o : g.outputs) {
    const std::string unit = shown_unit(o);
    units.push_back(cpp_string(unit));
    any_unit = any_unit || !unit.empty();
  }
  if (any_unit)
    c.public_methods.push_back({"", "std::vector<std::string> output_units() const override",
                                {CppStmt::line(fmt::format("return {{{}}};", fmt::join(units, ", ")))}});
  CppFunction params{"", "std::vector<mbgrt::ParameterInfo> parameters() const override", {}};
  std::vector<std::string> infos;
  // A parameter declared in a unit is listed, and set, in that unit (`angle`
  // in deg); inside, and in the CSV, it is in SI.
  bool scaled = false;
  for (const Parameter& p : g.params) {
    std::string value = p.literal ? cpp_double(p.literal_value)
                        : compact ? "computed"
                                  : "std::numeric_limits<double>::quiet_NaN()";
    std::string doc = p.literal ? "" : computed_doc(p, g);
    if (p.unit && p.literal) {  // (converted back to 15 digits: `30 {deg}` lists 30)
      if (!p.unit->unit.is_si()) value = cpp_double(std::stod(fmt::format("{:.15g}", p.literal_value / p.unit->unit.scale)));
      doc = p.unit->unit.text;
    }
    scaled = scaled || (p.unit && !p.unit->unit.is_si());
    const std::string si = p.dimension ? units::format(*p.dimension) : "";
    infos.push_back(fmt::format("{{{}, {}, {}, {}}}", cpp_string(p.name), value, cpp_string(doc), cpp_string(si)));
  }
  if (infos.empty()) {
    params.body.push_back(CppStmt::line("return {};"));
  } else if (compact) {
    // Thousands (the bodies' initial poses): a table of constants, not a list
    // of ParameterInfo to construct (g++ -O2 took 55 s for 1,865 of them),
    // a computed parameter's value (NaN, it has none of its own) named once.
    params.body.push_back(CppStmt::line("constexpr double computed = std::numeric_limits<double>::quiet_NaN();"));
    params.body.push_back(CppStmt::line("struct Row {"));
    params.body.push_back(CppStmt::line("  const char* name;"));
    params.body.push_back(CppStmt::line("  double value;"));
    params.body.push_back(CppStmt::line("  const char* doc;"));
    params.body.push_back(CppStmt::line("  const char* unit;"));
    params.body.push_back(CppStmt::line("};"));
    params.body.push_back(CppStmt::line("static const Row kRows[] = {"));
    for (const std::string& s : infos) params.body.push_back(CppStmt::line("    " + s + ","));
    params.body.push_back(CppStmt::line("};"));
    params.body.push_back(CppStmt::line("std::vector<mbgrt::ParameterInfo> out;"));
    params.body.push_back(CppStmt::line("for (const Row& r : kRows) out.push_back({r.name, r.value, r.doc, r.unit});"));
    params.body.push_back(CppStmt::line("return out;"));
  } else {
    params.body.push_back(CppStmt::line("return {"));
    for (const std::string& s : infos) params.body.push_back(CppStmt::line("    " + s + ","));
    params.body.push_back(CppStmt::line("};"));
  }
  c.public_methods.push_back(params);
  if (s.dae) {
    CppFunction ids{"", "void differential_ids(double* id) const override", {}};
    if (compact) {  // states, then algebraic unknowns
      ids.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = 0; i < {}; ++i) id[i] = 1.0;", s.states.size())));
      ids.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = {}; i < {}; ++i) id[i] = 0.0;", s.states.size(), unknowns)));
    }
    for (std::size_t i = 0; i < unknowns && !compact; ++i)
      ids.body.push_back(CppStmt::line(fmt::format("id[{}] = {};", i, i < s.states.size() ? "1.0" : "0.0")));
    c.public_methods.push_back(ids);
    c.public_methods.push_back({"", "bool is_dae() const override", {CppStmt::line("return true;")}});
  }
  CppFunction settings{"Defaults from the model's simulate { } block; the command line overrides them.",
                       "mbgrt::Settings default_settings() const override", {CppStmt::line("mbgrt::Settings s;")}};
  const SimSettings& ss = g.settings;
  if (ss.t_end) settings.body.push_back(CppStmt::line(fmt::format("s.t_end_s = {};", cpp_double(*ss.t_end))));
  if (ss.interval) settings.body.push_back(CppStmt::line(fmt::format("s.interval_s = {};", cpp_double(*ss.interval))));
  std::string solver =
      ss.solver.value_or(mbgrt::integrator_info(s.dae ? mbgrt::kDefaultDaeSolver : mbgrt::kDefaultOdeSolver).name);
  settings.body.push_back(CppStmt::line(fmt::format("s.solver = mbgrt::Solver::{};", solver)));
  if (ss.rtol) settings.body.push_back(CppStmt::line(fmt::format("s.rtol = {};", cpp_double(*ss.rtol))));
  if (ss.atol) settings.body.push_back(CppStmt::line(fmt::format("s.atol = {};", cpp_double(*ss.atol))));
  if (ss.step) settings.body.push_back(CppStmt::line(fmt::format("s.step_s = {};", cpp_double(*ss.step))));
  if (ss.rho_inf) settings.body.push_back(CppStmt::line(fmt::format("s.rho_inf = {};", cpp_double(*ss.rho_inf))));
  if (ss.accuracy) settings.body.push_back(CppStmt::line(fmt::format("s.accuracy = {};", cpp_double(*ss.accuracy))));
  settings.body.push_back(CppStmt::line("return s;"));
  c.public_methods.push_back(settings);
  CppFunction set{"", "bool set_parameter(const std::string& name, double value) override", {}};
  if (g.params.empty()) {
    set.body.push_back(CppStmt::line("(void)name;"));
    set.body.push_back(CppStmt::line("(void)value;"));
    set.body.push_back(CppStmt::line("return false;"));
  } else if (compact) {  // the names parameters() lists, not a second list of thousands
    set.body.push_back(CppStmt::line("const std::vector<mbgrt::ParameterInfo> all = parameters();"));
    set.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = 0; i < {}; ++i) {{", g.params.size())));
    set.body.push_back(CppStmt::line("  if (name != all[i].name) continue;"));
  } else {
    std::vector<std::string> pn;
    for (const Parameter& p : g.params) pn.push_back(cpp_string(p.name));
    set.body.push_back(CppStmt::line(fmt::format("static const char* const kParams[] = {{{}}};", fmt::join(pn, ", "))));
    set.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = 0; i < {}; ++i) {{", g.params.size())));
    set.body.push_back(CppStmt::line("  if (name != kParams[i]) continue;"));
  }
  if (!g.params.empty()) {
    if (scaled) {  // to SI from the declared units, before the loop
      std::vector<std::string> scales;
      for (const Parameter& p : g.params) scales.push_back(cpp_double(p.unit ? p.unit->unit.scale : 1.0));
      set.body.insert(set.body.end() - 2, CppStmt::line(fmt::format("static const double kToSI[] = {{{}}};",
                                                                     fmt::join(scales, ", "))));
    }
    set.body.push_back(CppStmt::line(scaled ? "  overrides_[i] = value * kToSI[i];" : "  overrides_[i] = value;"));
    set.body.push_back(CppStmt::line("  overridden_[i] = true;"));
    set.body.push_back(CppStmt::line("  return true;"));
    set.body.push_back(CppStmt::line("}"));
    set.body.push_back(CppStmt::line("return false;"));
  }
  c.public_methods.push_back(set);
}

std::string shown_unit(const Output& o) {
  if (o.unit) return o.unit->unit.text;
  return o.dimension && !o.dimension->is_none() ? units::format(*o.dimension) : "";
}

CppFunction residual_sparsity_method(const ir::ReducedSystem& s) {
  std::vector<long> starts{0}, rows;
  for (const std::vector<int>& column : s.residual_pattern) {
    rows.insert(rows.end(), column.begin(), column.end());
    starts.push_back(static_cast<long>(rows.size()));
  }
  CppFunction f{fmt::format("SPARSITY: where IDA's matrix dF/dy + c_j dF/dy' can be nonzero, by column (compressed "
                            "sparse columns: {} of {} entries)",
                            rows.size(), s.residual_pattern.size() * s.residual_pattern.size()),
                "bool residual_sparsity(std::vector<long>& column_starts, std::vector<long>& rows) const override",
                {}};
  static_table(f.body, "long", "kStarts", starts);
  static_table(f.body, "long", "kRows", rows);
  f.body.push_back(CppStmt::line(fmt::format("column_starts.assign(kStarts, kStarts + {});", starts.size())));
  f.body.push_back(CppStmt::line(fmt::format("rows.assign(kRows, kRows + {});", rows.size())));
  f.body.push_back(CppStmt::line("return true;"));
  return f;
}

}  // namespace mbgc::codegen
