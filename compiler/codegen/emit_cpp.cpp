#include "codegen/emit_cpp.hpp"

#include <algorithm>
#include <iterator>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <set>
#include <stdexcept>
#include <type_traits>

#include "codegen/constraints.hpp"
#include "codegen/cse.hpp"
#include "codegen/cpp.hpp"
#include "codegen/derived_constants.hpp"
#include "codegen/drawings.hpp"
#include "codegen/energy.hpp"
#include "codegen/entry_point.hpp"
#include "codegen/events.hpp"
#include "codegen/identity.hpp"
#include "codegen/names.hpp"
#include "codegen/outline.hpp"
#include "codegen/outline_emit.hpp"
#include "codegen/render.hpp"
#include "codegen/shared_values.hpp"
#include "codegen/split.hpp"
#include "codegen/stats.hpp"
#include "codegen/template.hpp"
#include "units/unit.hpp"

namespace mbgc::codegen {
namespace {

using namespace mbgc::ir;

class Emitter {
 public:
  Emitter(const ReducedSystem& sys, const SourceManager& sources, const EmitOptions& opt)
      : s_(sys), g_(sys.graph), sources_(sources), opt_(opt),
        outline_(sys, opt.outline, mangle_, names_, [this](const SourceLoc& l) { return where(l); }, cse_counter_) {
    // fmt::format, not "p" + std::to_string(i): GCC 12 at -O3 reports a false
    // -Wrestrict on operator+(const char*, std::string&&) (GCC PR 105329).
    for (std::size_t i = 0; i < g_.params.size(); ++i) mangle_.get(fmt::format("p{}", i), g_.params[i].name);
    for (std::size_t i = 0; i < g_.vars.size(); ++i) mangle_.get(fmt::format("v{}", i), g_.vars[i].name);
    names_.var = [this](int id) {
      if (const std::string* at = outline_.stored_name(id)) return *at;
      if (witness_active_)
        if (auto it = witness_names_.find(id); it != witness_names_.end()) return it->second;
      if (auto it = discrete_name_.find(id); it != discrete_name_.end()) return it->second;
      return mangle_.get(fmt::format("v{}", id), "");
    };
    names_.param = [this](int id) { return mangle_.get(fmt::format("p{}", id), ""); };
    class_name_ = mangle_.get("class", g_.model_name + "_model");
    model_dir_ = std::filesystem::path(opt_.source_display).parent_path();
  }

  std::string run(EmitStats* stats) {
    CppClass c;
    c.name = class_name_;
    c.base = "mbgrt::Model";
    compact_ = outline_.measure_dynamics();
    add_identity_methods(c, s_, opt_, compact_);
    find_derived_constants(s_, hoisted_, hoisted_order_);
    for (std::size_t k = 0; k < s_.events.size(); ++k) hoisted_[s_.events[k].step] = event_mode_name(k);  // printed as their modes
    discrete_name_ = contact_member_names(s_);
    c.public_methods.push_back(initial());
    if (any_nominal())
      c.public_methods.push_back({"NOMINAL: unknown i's absolute tolerance is atol x nominal(i) (set in initial()).",
                                  "double nominal(std::size_t i) const override",
                                  {CppStmt::line(fmt::format("return i < {} ? nominal_[i] : 1.0;", unknown_count()))}});
    if (s_.dae) {
      add_long_method(c, residual());
    } else if (s_.energy.available) {  // the powers read what the derivative computes: one pass gives both
      add_long_method(c, derivative_and_power());
      c.public_methods.push_back(
          {"DERIVATIVE: the state derivatives (derivative_and_power() computes them, and the powers where asked).",
           "void derivative(double t, const double* x, double* xdot) override",
           {CppStmt::line("derivative_and_power(t, x, xdot, nullptr);")}});
    } else {
      add_long_method(c, derivative());
    }
    if (!s_.dae && has_velocity_state()) {
      c.public_methods.push_back({"", "bool has_position_rates() const override", {CppStmt::line("return true;")}});
      add_long_method(c, position_rates());
    }
    if (s_.dae && !s_.residual_pattern.empty()) c.public_methods.push_back(residual_sparsity_method(s_));
    if (!s_.jacobian.empty()) {
      c.public_methods.push_back({"", "bool has_jacobian() const override", {CppStmt::line("return true;")}});
      add_long_method(c, jacobian());
    }
    c.public_methods.push_back(outputs());
    if (!g_.drawings.empty()) add_drawing_methods(c, s_, body_poses());
    if (!s_.events.empty()) c.public_methods.push_back(event_functions());
    add_event_methods(c, s_, where_fn());
    if (!s_.contacts.empty()) {
      const bool friction = std::any_of(s_.contacts.begin(), s_.contacts.end(), [](const ContactRow& r) { return bool(r.friction); });
      add_contact_methods(c, s_, contact_speeds(), friction ? std::optional<CppFunction>(contact_tangents()) : std::nullopt);
    }
    add_held_state_methods(c, s_);
    if (opt_.entry_point && !g_.params.empty()) {  // an FMU's calculated parameters read them
      CppFunction values{"PARAMETER VALUES: each parameter as initial() set it (SI), in parameters() order.",
                         "bool parameter_values(double* out) const override", {}};
      for (std::size_t i = 0; i < g_.params.size(); ++i)
        values.body.push_back(CppStmt::line(fmt::format("out[{}] = {};", i, names_.param(static_cast<int>(i)))));
      values.body.push_back(CppStmt::line("return true;"));
      c.public_methods.push_back(std::move(values));
    }
    if (!s_.constraints.empty()) constraint_functions(c);
    std::optional<EnergyMethods> energy;
    if (s_.energy.available) {
      const std::vector<Expr> stored = {stored_energy_value(s_)}, powers = power_values(s_);
      if (shares_witness_values()) witness_values(c, stored, powers);
      energy = EnergyMethods{
          values_at("STORED ENERGY: H at (t, y), every linear storage's (the energy witness).", "stored_energy", "out",
                    stored, s_.for_energy, "the stored energy", {}, true),
          values_at("POWER at (t, y): out[0] what the sources deliver, out[1] what the rest absorbs (the energy witness).",
                    "power", "out", powers, s_.for_power, "the powers", {}, true)};
    }
    add_energy_methods(c, s_, where_fn(), std::move(energy));
    c.public_methods.push_back({"TERMINAL: nothing to do at the end of a run.",
                                "void terminal(double t, const double* y) override", {CppStmt::line("(void)t;"), CppStmt::line("(void)y;")}});
    for (CppFunction& f : outline_.functions()) c.private_methods.push_back(std::move(f));
    private_part(c);

    std::string banner = fmt::format(
        "// Generated by mbgc {} from {} — do not edit.\n"
        "// Model `{}`: {} state{}, {} output{}, {} parameter{}{}.\n"
        "// Each equation's comment names the model line it comes from.",
        opt_.version, opt_.source_display, g_.model_name, s_.states.size(), s_.states.size() == 1 ? "" : "s",
        g_.outputs.size(), g_.outputs.size() == 1 ? "" : "s", g_.params.size(), g_.params.size() == 1 ? "" : "s",
        s_.dae ? fmt::format(", DAE with {} algebraic unknown{} (IDA)", s_.algebraic.size(), s_.algebraic.size() == 1 ? "" : "s") : "");
    if (!opt_.scene.empty())
      banner += fmt::format("\n// Scene `{0}` (mbgc --scene {0}): only what its outputs need; mbgc --explain-scene {0} "
                            "lists what was removed.",
                            opt_.scene);
    std::string body;
    std::string entry;
    if (opt_.library) {
      const std::string& ns = opt_.library_namespace;
      banner += "\n// Library form (mbgc --library): include this file and instantiate " + ns + "::" + class_name_ + ".\n#pragma once";
      body = "namespace " + ns + " {\n\n" + print(c) + "\n}  // namespace " + ns + "\n";
    } else {
      body = "namespace {\n\n" + print(c) + "\n}  // namespace\n";
      entry = opt_.entry_point ? opt_.entry_point(class_name_)
                               : simulator_main({class_name_, !g_.drawings.empty(), s_.dae && !s_.residual_pattern.empty()});
    }
    std::string out = kSimulatorTemplate;
    replace(out, "{{banner}}", banner);
    replace(out, "{{model_class}}", body);
    replace(out, "{{entry_point}}", entry);
    // No trailing blank lines: one newline at the end.
    while (out.size() > 1 && out[out.size() - 1] == '\n' && out[out.size() - 2] == '\n') out.pop_back();
    if (stats) *stats = collect_stats(c, out, costs_, s_);
    return out;
  }

  Where where_fn() const {
    return [this](const SourceLoc& loc) { return where(loc); };
  }

  /// A method that may be long (the dynamics, the Jacobian): past
  /// kMaxMethodLines statements it is cut into parts (codegen/split.hpp).
  void add_long_method(CppClass& c, CppFunction f, bool is_private = false) {
    auto split = split_method(f, kMaxMethodLines);
    std::vector<CppFunction>& methods = is_private ? c.private_methods : c.public_methods;
    if (!split) {
      methods.push_back(std::move(f));
      return;
    }
    methods.push_back(std::move(split->method));
    for (CppFunction& part : split->parts) c.private_methods.push_back(std::move(part));
    for (std::string& m : split->members)
      if (std::find(scratch_.begin(), scratch_.end(), m) == scratch_.end()) scratch_.push_back(std::move(m));
  }

  /// What a method's expressions and linear solves cost, counted as they are printed.
  using Cost = MethodCost;
  /// While the returned guard lives, printed expressions count towards method `f`.
  struct Counting {
    Cost*& cost;
    ~Counting() { cost = nullptr; }
  };
  [[nodiscard]] Counting count_into(const CppFunction& f) {
    cost_ = &costs_[f.signature];
    cost_signature_ = f.signature;
    return Counting{cost_};
  }

 private:
  static void replace(std::string& s, const std::string& key, const std::string& value) {
    auto pos = s.find(key);
    if (pos != std::string::npos) s.replace(pos, key.size(), value);
  }

  /// "file:line:col", the file relative to the model's directory where it
  /// is inside it (the banner names the model's path): every comment says
  /// "n_four_bar.mbg:20:8", however mbgc was given the model.
  std::string where(const SourceLoc& loc) const {
    if (!loc.valid()) return "(generated)";
    const std::string& path = sources_.file(loc.file).display_path;
    std::filesystem::path shown = path;
    if (!model_dir_.empty())
      if (std::filesystem::path rel = shown.lexically_relative(model_dir_); !rel.empty() && *rel.begin() != "..") shown = rel;
    return fmt::format("{}:{}:{}", shown.string(), loc.line, loc.col);
  }

  /// Where a parameter's line comes from: `  // FILE:LINE:COL` at its end,
  /// or (compact_) a comment heading each run of lines from the same place,
  /// as an equation's does (a body's parameters are its declaration's).
  class Located {
   public:
    Located(const Emitter& e, std::vector<CppStmt>& body) : e_(e), body_(body) {}
    /// What ends the line: "  // FILE:LINE:COL", or "" after the heading comment (if a new place).
    std::string head(const SourceLoc& loc) {
      std::string at = e_.where(loc);
      if (!e_.compact_) return "  // " + at;
      if (at != last_) body_.push_back(CppStmt::comment(at));
      last_ = std::move(at);
      return {};
    }
    void restart() { last_.clear(); }

   private:
    const Emitter& e_;
    std::vector<CppStmt>& body_;
    std::string last_;
  };

  std::string var_name(int id) const { return names_.var(id); }
  /// Its name in the model ("crank0.q.q[1]").
  const std::string& var_name_in_model(int id) const { return g_.vars[static_cast<std::size_t>(id)].name; }

  std::size_t unknown_count() const { return s_.states.size() + s_.algebraic.size(); }

  // ---- INITIAL -------------------------------------------------------------------------
  CppFunction initial() {
    CppFunction f{"INITIAL: parameters (honouring --set overrides), then the initial state.",
                  fmt::format("void initial(double t, double* {}, double* yp) override", s_.dae ? "y" : "x"), {}};
    const Counting counting = count_into(f);
    f.body.push_back(CppStmt::line("(void)t;"));
    if (s_.states.empty() && s_.algebraic.empty()) f.body.push_back(CppStmt::line(s_.dae ? "(void)y;" : "(void)x;"));
    if (!s_.dae) f.body.push_back(CppStmt::line("(void)yp;"));
    if (!g_.params.empty()) f.body.push_back(CppStmt::comment("CONSTANTS / PARAMETERS"));
    // Derived parameters (a joint frame from its axis, an initial pose along a
    // chain) repeat subexpressions: they are shared here too (codegen/cse).
    // A parameter only reads earlier ones, so a temporary defined before its
    // first use reads parameters that are already set (overrides included).
    const std::size_t from = f.body.size();
    Located located(*this, f.body);
    for (std::size_t i = 0; i < g_.params.size(); ++i) {
      const Parameter& p = g_.params[i];
      std::string at = located.head(p.loc);
      // its unit: as declared (`{kg}`), else the SI unit the units pass found (`[N*s/m]`)
      if (p.unit) at += fmt::format("{}{{{}}}", at.empty() ? "  // " : ", ", p.unit->unit.text);
      else if (p.dimension && !p.dimension->is_none()) at += fmt::format("{}[{}]", at.empty() ? "  // " : ", ", units::format(*p.dimension));
      f.body.push_back(CppStmt::param(names_.param(static_cast<int>(i)), i, p.value, std::move(at)));
    }
    if (!hoisted_order_.empty()) f.body.push_back(CppStmt::comment("DERIVED CONSTANTS: parameter expressions, computed once per run"));
    for (const Expr& e : hoisted_order_) {
      f.body.push_back(CppStmt::assign(hoisted_.at(e), e));
      f.body.back().may_name = CppStmt::Naming::always;  // a derived constant that recurs whole is read by its name
    }
    for (std::size_t c = 0; c < s_.contacts.size(); ++c)
      f.body.push_back(CppStmt::assign(fmt::format("contact_restitution_[{}]", c), s_.contacts[c].restitution,
                                       "  // " + where(s_.contacts[c].loc)));
    if (!s_.states.empty()) f.body.push_back(CppStmt::comment("INITIAL STATE"));
    const char* y = s_.dae ? "y" : "x";
    located.restart();
    for (std::size_t i = 0; i < s_.states.size(); ++i) {
      const StateVar& st = s_.states[i];
      const Variable& v = g_.vars[static_cast<std::size_t>(st.var)];
      if (compact_) located.head(v.loc);
      const std::string at = compact_ ? "" : fmt::format(" ({})", where(v.loc));
      f.body.push_back(CppStmt::assign(fmt::format("{}[{}]", y, i), st.initial, fmt::format("  // {}{}", v.name, at)));
    }
    if (any_nominal()) {
      f.body.push_back(CppStmt::comment("NOMINAL SIZES: each unknown's absolute tolerance is atol x nominal (reduce/nominal.hpp)"));
      f.body.push_back(CppStmt::line("for (double& v : nominal_) v = 1.0;"));
      for (std::size_t i = 0; i < s_.nominal.size(); ++i) {
        if (is_one(s_.nominal[i])) continue;
        const Variable& v = g_.vars[static_cast<std::size_t>(s_.states[i].var)];
        f.body.push_back(CppStmt::assign(fmt::format("nominal_[{}]", i), s_.nominal[i], "  // " + v.name));
      }
    }
    const ExprNames none;
    share_subexpressions(f.body, from, none, cse_counter_);
    render(f.body, from, none, names_, ops());
    if (s_.dae) {
      if (compact_ && !s_.algebraic.empty())  // (their names: variable_name(i))
        f.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = {}; i < {}; ++i) y[i] = 0.0;  // the algebraic unknowns: "
                                                   "first guess, made consistent by IDA",
                                                   s_.states.size(), unknown_count())));
      for (std::size_t j = 0; j < s_.algebraic.size() && !compact_; ++j)
        f.body.push_back(CppStmt::line(fmt::format("y[{}] = 0.0;  // {}: first guess, made consistent by IDA", s_.states.size() + j,
                                                   g_.vars[static_cast<std::size_t>(s_.algebraic[j])].name)));
      f.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = 0; i < {}; ++i) yp[i] = 0.0;  // first guess", unknown_count())));
    }
    return f;
  }

  // ---- sections with equations ------------------------------------------------------------
  /// Read the unknowns a section uses, compute its assignments, then its results.
  /// `exporting`: the section is witness_values()'s, whose exported variables
  /// are set as members (or kept in their outlined runs' arrays) for its callers.
  /// `optional` names an output array the caller may pass as null
  /// (derivative_and_power's `rate`): the results into it are written inside
  /// `if (rate) { ... }`, their shared subexpressions before it.
  void section(std::vector<CppStmt>& body, const std::vector<int>& assignment_indices, std::vector<SectionResult> results,
               const std::string& results_comment, bool exporting = false, const char* optional = nullptr) {
    // Which variables does this section touch?
    std::unordered_set<int> used;
    std::set<int> blocks_read;  // a block's unknowns share its inputs: read them once
    for (int i : assignment_indices) {
      const Assignment& a = s_.assignments[static_cast<std::size_t>(i)];
      if (a.block >= 0 && !blocks_read.insert(a.block).second) continue;
      assignment_inputs(s_, a, used);
    }
    collect_vars(result_values(results), used);
    const char* y = s_.dae ? "y" : "x";
    bool any_read = false;
    for (std::size_t i = 0; i < s_.states.size(); ++i) {
      int v = s_.states[i].var;
      if (!used.count(v)) continue;
      if (!any_read) body.push_back(CppStmt::comment(s_.dae ? "unknowns from the integrator" : "states"));
      any_read = true;
      body.push_back(CppStmt::read(var_name(v), y, i));
    }
    for (std::size_t j = 0; j < s_.algebraic.size(); ++j) {
      int v = s_.algebraic[j];
      if (!used.count(v)) continue;
      body.push_back(CppStmt::read(var_name(v), "y", s_.states.size() + j));
    }
    for (std::size_t i = 0; i < s_.derivative_unknowns.size(); ++i) {
      int v = s_.derivative_unknowns[i];
      if (v < 0 || !used.count(v)) continue;
      body.push_back(CppStmt::read(var_name(v), "yp", i));
    }
    // Bodies whose equations are the same up to names: one function per shape (codegen/outline).
    std::vector<const Assignment*> list;
    for (int i : assignment_indices) list.push_back(&s_.assignments[static_cast<std::size_t>(i)]);
    Outlined outlined_form = outline_.outline_section(list, results, method_name(cost_signature_), exporting ? &witness_.exported : nullptr);
    const Outlining& outlined = outlined_form.o;
    const std::vector<std::string>& store = outlined_form.store;
    const std::vector<int>& run_at = outlined_form.run_at;
    const std::vector<int>& copy_after = outlined_form.copy_after;
    const std::vector<int>& result_run_at = outlined_form.result_run_at;
    const std::size_t from = body.size();
    std::set<int> blocks_done;
    std::string last_origin;
    for (std::size_t k = 0; k < list.size(); ++k) {
      const Assignment& a = *list[k];
      if (run_at[k] >= 0) {
        const OutlinedRun& run = outlined.runs[static_cast<std::size_t>(run_at[k])];
        if (run.begin == k) outline_.call_shape(body, outlined_form, run_at[k], list, results, *ops());
        last_origin.clear();
        continue;
      }
      if (a.block >= 0) {
        if (blocks_done.insert(a.block).second) emit_block(body, a);
        body.push_back(defined(a.var, exporting, fmt::format("blk{}_x[{}]", a.block + 1, block_position(a))));
        continue;
      }
      // One comment heads each run of assignments from the same model line and origin.
      std::string origin = fmt::format("{}  {}", where(a.loc), a.origin);
      if (origin != last_origin) body.push_back(CppStmt::comment(origin));
      last_origin = std::move(origin);
      body.push_back(defined(a.var, exporting, a.value));
      if (const int r = copy_after[k]; r >= 0) {
        const OutlinedRun& run = outlined.runs[static_cast<std::size_t>(r)];
        for (std::size_t j = 0; j < run.outputs.size(); ++j)
          body.push_back(
              CppStmt::assign(fmt::format("{}[{}]", store[static_cast<std::size_t>(r)], run.slots[j]), var_name(run.defined[run.outputs[j]])));
      }
    }
    if (!results.empty()) body.push_back(CppStmt::comment(results_comment));
    bool guarded = false;  // inside `if (optional) {`
    for (std::size_t i = 0; i < results.size(); ++i) {
      if (const int r = result_run_at[i]; r >= 0) {
        if (outlined.runs[static_cast<std::size_t>(r)].begin == i) outline_.call_shape(body, outlined_form, r, list, results, *ops());
        continue;
      }
      const bool inside = optional && results[i].array == optional;
      if (inside && !guarded) body.push_back(CppStmt::line(fmt::format("if ({}) {{", optional)));
      body.push_back(CppStmt::assign(fmt::format("{}{}[{}]", inside ? "  " : "", results[i].array, results[i].index),
                                     results[i].value, results[i].note));
      body.back().with_previous = inside;
      guarded = guarded || inside;
    }
    if (guarded) {
      body.push_back(CppStmt::line("}"));
      body.back().with_previous = true;
    }
    // Common subexpressions: anything non-trivial used twice or more in this section.
    share_subexpressions(body, from, hoisted_, cse_counter_);
    render(body, from, hoisted_, names_, ops());
    if (exporting)  // what the callers read: its place in an outlined run's array, else its member
      for (int i : witness_.assignments)
        if (const int v = s_.assignments[static_cast<std::size_t>(i)].var; witness_.exported.count(v)) {
          witness_names_[v] = var_name(v);
          if (!outline_.stored_name(v)) witness_members_.push_back(var_name(v));
        }
    outline_.finish_section(outlined_form);
    witness_active_ = false;
  }

  /// A section's assignment of `value` to `var`: a local, or (an exported
  /// variable of witness_values()) its member. An equation's value may
  /// become a shared name (codegen/cse); one read from a place (a linear
  /// block's solution) is C++ already.
  template <class Value>
  CppStmt defined(int var, bool exporting, Value value) const {
    CppStmt st = exporting && witness_.exported.count(var) ? CppStmt::assign(var_name(var), std::move(value))
                                                           : CppStmt::local(var_name(var), std::move(value));
    if constexpr (std::is_same_v<Value, Expr>) st.may_name = CppStmt::Naming::unnamed;
    return st;
  }

  // ---- what the energy witness's two methods compute alike (codegen/shared_values) ----
  /// Whether the energy witness's methods share witness_values(): where the
  /// methods' bodies are outlined (--outline always, or auto on large
  /// dynamics), so that the file is written compactly.
  bool shares_witness_values() const {
    if (opt_.outline == EmitOptions::Outline::never) return false;
    return opt_.outline == EmitOptions::Outline::always || outline_.large();
  }

  /// WITNESS VALUES: the assignments power() and stored_energy() need, once
  /// per call of each (a private method); `stored` and `powers` are their results.
  void witness_values(CppClass& c, const std::vector<Expr>& stored, const std::vector<Expr>& powers) {
    std::vector<Expr> read = powers;
    read.insert(read.end(), stored.begin(), stored.end());
    // the union, unless stored_energy() would then do more than twice its own work
    std::vector<int> either;
    std::set_union(s_.for_power.begin(), s_.for_power.end(), s_.for_energy.begin(), s_.for_energy.end(), std::back_inserter(either));
    const Sharing sharing = either.size() > 2 * s_.for_energy.size() ? Sharing::common : Sharing::all;
    witness_ = find_shared_values(s_, {&s_.for_power, &s_.for_energy}, read, sharing);
    if (witness_.empty()) return;
    const char* y = s_.dae ? "y" : "x";
    CppFunction f{fmt::format("WITNESS VALUES: what power() and stored_energy() {}, at "
                              "(t, {}); each calls it first and reads them from members.",
                              sharing == Sharing::all ? "both read (the velocities, the forces)"
                                                      : "both read (the velocities; each computes the rest it needs)",
                              y),
                  fmt::format("void witness_values(double t, const double* {}{})", y, s_.dae ? ", const double* yp" : ""),
                  {CppStmt::line("(void)t;"), CppStmt::line(fmt::format("(void){};", y))}};
    if (s_.dae) f.body.push_back(CppStmt::line("(void)yp;"));
    {
      const Counting counting = count_into(f);
      section(f.body, witness_.assignments, {}, "", true);
    }
    // its work counts in each caller, once per call (as a shape function's)
    witness_cost_ = costs_.at(f.signature);
    costs_.erase(f.signature);
    witness_call_ = s_.dae ? "witness_values(t, y, yp);" : "witness_values(t, x);";
    add_long_method(c, std::move(f), true);
  }

  /// A caller of witness_values(): the call, then the rest of `slice` (what
  /// the call does not compute), the shared variables named by their members.
  std::vector<int> call_witness_values(std::vector<CppStmt>& body, const std::vector<int>& slice) {
    if (witness_.empty()) return slice;
    body.push_back(CppStmt::comment("witness_values() sets the members read below"));
    body.push_back(CppStmt::line(witness_call_));
    *ops() += witness_cost_.ops;
    cost_->solves.insert(cost_->solves.end(), witness_cost_.solves.begin(), witness_cost_.solves.end());
    witness_active_ = true;
    return witness_.rest_of(slice);
  }

  std::size_t block_position(const Assignment& a) const {
    const LinearBlock& lb = s_.linear_blocks[static_cast<std::size_t>(a.block)];
    return static_cast<std::size_t>(std::find(lb.unknowns.begin(), lb.unknowns.end(), a.var) - lb.unknowns.begin());
  }

  /// A numerically solved loop: fill A and b, solve in place.
  void emit_block(std::vector<CppStmt>& body, const Assignment& a) {
    const LinearBlock& lb = s_.linear_blocks[static_cast<std::size_t>(a.block)];
    std::size_t n = lb.unknowns.size();
    std::vector<std::string> names;
    for (int u : lb.unknowns) names.push_back(g_.vars[static_cast<std::size_t>(u)].name);
    body.push_back(CppStmt::comment(fmt::format("{}  {}", where(a.loc), a.origin)));
    body.push_back(CppStmt::comment(fmt::format("A x = b for x = ({})", fmt::join(names, ", "))));
    std::string id = fmt::format("blk{}", a.block + 1);
    body.push_back(CppStmt::array_of(id + "_a", lb.a, n));
    body.push_back(CppStmt::array_of(id + "_x", lb.b));
    body.back().with_previous = true;
    if (lb.rank_revealing) {
      // rows the others imply at this configuration: recorded for the run summary
      std::vector<std::string> rows;
      for (int u : lb.unknowns) rows.push_back(cpp_string(g_.vars[static_cast<std::size_t>(u)].name));
      body.push_back(CppStmt::line(fmt::format("static const char* const {}_rows[] = {{{}}};", id, fmt::join(rows, ", "))));
      body.push_back(CppStmt::line(fmt::format("int {}_dependent[{}];", id, n)));
      body.push_back(CppStmt::line(fmt::format("double {}_closest;", id)));
      body.push_back(CppStmt::line(fmt::format(
          "const int {0}_rank = mbgrt::solve_rank_revealing<{1}>({0}_a, {0}_x, 1e-10, {0}_dependent, &{0}_closest);", id,
          n)));
      body.push_back(CppStmt::line(fmt::format(
          "rank_loss_.observe(t, \"the {1} x {1} system of the {2} multipliers\", {0}_rank, {1}, {0}_dependent, "
          "{0}_rows, {0}_closest, {3});",
          id, n, lb.cut_joints ? "cut joints'" : "constraint", lb.cut_joints ? "true" : "false")));
      has_rank_loss_ = true;
    } else {
      body.push_back(CppStmt::line(fmt::format("mbgrt::solve_linear({}, {}_a, {}_x);", n, id, id)));
    }
    if (!cost_) throw std::logic_error("mbgc: a linear solve outside a counted method (codegen bug)");
    cost_->solves.push_back(n);
  }

  /// Where the operations of printed text go: the method being built.
  CppOps* ops() {
    if (!cost_) throw std::logic_error("mbgc: an expression printed outside a counted method (codegen bug)");
    return &cost_->ops;
  }

  /// xdot[i] = the derivative of state i, each named by the body it is
  /// about: every state's, or the positions' alone.
  std::vector<SectionResult> state_derivatives(bool positions_only) {
    std::vector<SectionResult> results;
    for (std::size_t i = 0; i < s_.states.size(); ++i)
      if (!positions_only || is_position_state(s_, i))
        results.push_back({"xdot", i, s_.state_derivative[i], owner_of(var_name_in_model(s_.states[i].var)), {}, {}});
    return results;
  }

  CppFunction derivative() {
    CppFunction f{"DERIVATIVE: the state derivatives, in causal order.",
                  "void derivative(double t, const double* x, double* xdot) override", {CppStmt::line("(void)t;"), CppStmt::line("(void)x;")}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results = state_derivatives(false);
    if (results.empty()) f.body.push_back(CppStmt::line("(void)xdot;"));
    section(f.body, s_.for_derivative, std::move(results), "state derivatives");
    return f;
  }

  /// The derivative's equations and the powers' in one section: the powers
  /// read the kinematics and forces the derivative computes (for the
  /// 14-DOF two-track car, all but 2 of the 887 assignments they need), so
  /// the witness's explicit methods pay almost nothing for them.
  CppFunction derivative_and_power() {
    CppFunction f{"DERIVATIVE AND POWER: the state derivatives, in causal order, and the energy witness's powers: "
                  "rate[0] what the sources deliver, rate[1] what the rest absorbs (W).",
                  "void derivative_and_power(double t, const double* x, double* xdot, double* rate) override",
                  {CppStmt::line("(void)t;"), CppStmt::line("(void)x;")}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results = state_derivatives(false);
    if (results.empty()) f.body.push_back(CppStmt::line("(void)xdot;"));
    const std::vector<Expr> powers = power_values(s_);
    for (std::size_t k = 0; k < powers.size(); ++k) results.push_back({"rate", k, powers[k], {}, {}, {}});
    std::vector<int> slice;
    std::set_union(s_.for_derivative.begin(), s_.for_derivative.end(), s_.for_power.begin(), s_.for_power.end(),
                   std::back_inserter(slice));
    section(f.body, slice, std::move(results), "state derivatives, then the powers (when asked for)", false, "rate");
    return f;
  }

  bool has_velocity_state() const {
    for (std::size_t i = 0; i < s_.states.size(); ++i)
      if (!is_position_state(s_, i)) return true;
    return false;
  }

  /// The position states' derivatives alone (what they read of the
  /// kinematics), for the symplectic Euler: it takes them at the new
  /// velocities, after the derivative gave the velocities' rates.
  CppFunction position_rates() {
    CppFunction f{"POSITION RATES: the derivatives of the position states alone (the velocities' entries of xdot are "
                  "left as they are).",
                  "void position_rates(double t, const double* x, double* xdot) override",
                  {CppStmt::line("(void)t;"), CppStmt::line("(void)x;")}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results = state_derivatives(true);
    if (results.empty()) f.body.push_back(CppStmt::line("(void)xdot;"));
    section(f.body, s_.for_position_rates, std::move(results), "position derivatives");
    return f;
  }

  CppFunction jacobian() {
    std::size_t n = s_.states.size();
    CppFunction f{"JACOBIAN: d xdot_i / d x_j (row-major), derived symbolically, for the implicit solvers.",
                  "void jacobian(double t, const double* x, double* jac_out) override",
                  {CppStmt::line("(void)t;"), CppStmt::line("(void)x;"),
                   CppStmt::line(fmt::format("for (std::size_t k = 0; k < {}; ++k) jac_out[k] = 0.0;", n * n))}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results;
    for (std::size_t k = 0; k < s_.jacobian.size(); ++k)
      if (!is_zero(s_.jacobian[k])) results.push_back({"jac_out", k, s_.jacobian[k], {}, {}, {}});
    section(f.body, s_.for_jacobian, std::move(results), "nonzero entries");
    return f;
  }

  CppFunction residual() {
    CppFunction f{"RESIDUAL (DAE): r = F(t, y, yp) must vanish; states first, then algebraic unknowns.",
                  "void residual(double t, const double* y, const double* yp, double* r) override",
                  {CppStmt::line("(void)t;"), CppStmt::line("(void)y;"), CppStmt::line("(void)yp;")}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results;
    for (std::size_t i = 0; i < s_.residuals.size(); ++i) {
      // row i is unknown i's: y = [states, algebraic]
      const int unknown = i < s_.states.size() ? s_.states[i].var : s_.algebraic[i - s_.states.size()];
      const Residual& row = s_.residuals[i];
      results.push_back({"r", i, row.value, owner_of(var_name_in_model(unknown)), row.loc, row.origin});
    }
    section(f.body, s_.for_derivative, std::move(results), "residuals");
    return f;
  }

  /// The CN rows for assembly and drift reports: g (position level) for every
  /// row, then gdot (velocity level) for every row (their counts, names and
  /// multipliers: codegen/constraints.hpp).
  void constraint_functions(CppClass& c) {
    std::size_t n = s_.constraints.size();
    add_constraint_methods(c, s_);
    const char* y = s_.dae ? "y" : "x";
    CppFunction f{"CONSTRAINTS: g(x) for every CN row, then gdot(x).",
                  fmt::format("void constraints(double t, const double* {}, double* rows_out) override", y),
                  {CppStmt::line("(void)t;"), CppStmt::line(fmt::format("(void){};", y))}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results;
    for (std::size_t i = 0; i < n; ++i) {
      const ConstraintRow& row = s_.constraints[i];
      results.push_back({"rows_out", i, row.g, owner_of(row.name), row.loc, fmt::format("CN {}: g", row.name)});
    }
    for (std::size_t i = 0; i < n; ++i) {
      const ConstraintRow& row = s_.constraints[i];
      results.push_back({"rows_out", n + i, row.gdot, owner_of(row.name), row.loc, fmt::format("CN {}: gdot", row.name)});
    }
    section(f.body, s_.for_constraints, std::move(results), "g, then gdot");
    c.public_methods.push_back(f);
    constraint_jacobian(c);
  }

  /// G = dg/dx, symbolically (reduce/constraint_jacobian): its pattern by row,
  /// then its values in that order.
  void constraint_jacobian(CppClass& c) {
    const std::size_t n = s_.constraints.size();
    std::vector<long> starts{0}, columns;
    std::vector<SectionResult> results;
    for (std::size_t r = 0, k = 0; r < n; ++r) {
      const ConstraintRow& row = s_.constraints[r];
      for (; k < s_.constraint_jacobian.size() && s_.constraint_jacobian[k].row == static_cast<int>(r); ++k) {
        columns.push_back(s_.constraint_jacobian[k].state);
        results.push_back({"values", results.size(), s_.constraint_jacobian[k].value, owner_of(row.name), row.loc,
                           fmt::format("CN {}: dg/dx", row.name)});
      }
      starts.push_back(static_cast<long>(columns.size()));
    }
    CppFunction pattern{fmt::format("CONSTRAINT JACOBIAN: which states each CN row's g reads ({} entries, by row)",
                                    columns.size()),
                        "void constraint_jacobian_pattern(std::vector<long>& row_starts, std::vector<long>& columns) const override",
                        {}};
    static_table(pattern.body, "long", "kStarts", starts);
    static_table(pattern.body, "long", "kColumns", columns);
    pattern.body.push_back(CppStmt::line(fmt::format("row_starts.assign(kStarts, kStarts + {});", starts.size())));
    pattern.body.push_back(CppStmt::line(fmt::format("columns.assign(kColumns, kColumns + {});", columns.size())));
    c.public_methods.push_back(pattern);
    const char* y = s_.dae ? "y" : "x";
    CppFunction f{"CONSTRAINT JACOBIAN: dg/dx at (t, x), by symbolic differentiation, in the pattern's order.",
                  fmt::format("void constraint_jacobian(double t, const double* {}, double* values) override", y),
                  {CppStmt::line("(void)t;"), CppStmt::line(fmt::format("(void){};", y))}};
    if (results.empty()) f.body.push_back(CppStmt::line("(void)values;"));
    {
      const Counting counting = count_into(f);
      section(f.body, s_.for_constraint_jacobian, std::move(results), "dg/dx, by row");
    }
    add_long_method(c, std::move(f));
  }

  CppFunction outputs() {
    std::vector<Expr> values;
    std::vector<std::string> notes;  // each one's name, unit and line
    for (const Output& o : g_.outputs) {
      values.push_back(o.value);
      const std::string unit = shown_unit(o);
      notes.push_back(fmt::format("  // {}{} ({})", o.name, unit.empty() ? "" : " [" + unit + "]", where(o.loc)));
    }
    return values_at("OUTPUT: the declared outputs at (t, y).", "outputs", "out", values, s_.for_outputs,
                     "outputs, in declaration order", {}, false, notes);
  }

  CppFunction body_poses() {
    std::vector<Expr> values;
    std::vector<std::pair<std::string, SourceLoc>> owners;
    for (const DrawnBody& d : g_.drawings)
      for (const Expr& e : d.pose) values.push_back(e), owners.push_back({d.drawing->body, d.loc});
    for (const DrawnBody& d : g_.drawings)
      for (const Expr& e : d.modes) values.push_back(e);
    return values_at("POSES (--animate): each drawn body's origin and rotation, then the modal coordinates.", "body_poses",
                     "out", values, s_.for_drawings, "12 per body (origin, rotation row-major), then every modal coordinate", owners);
  }

  CppFunction event_functions() {
    std::vector<Expr> values;
    for (const EventRelation& ev : s_.events) values.push_back(ev.arg);
    return values_at("EVENTS: the zero-crossing functions, one per event (its step's argument).", "event_functions", "g",
                     values, s_.for_events, "zero-crossing functions, in event order");
  }

  CppFunction contact_speeds() {
    std::vector<Expr> values;
    for (const ContactRow& c : s_.contacts) values.push_back(c.rate);
    return values_at("CONTACT SPEEDS: dg/dt of each contact's gap.", "contact_speeds", "v", values, s_.for_contacts,
                     "contact speeds, in contact order");
  }

  CppFunction contact_tangents() {
    std::vector<Expr> values;
    for (const ContactRow& c : s_.contacts)
      for (int k = 0; k < 2; ++k) values.push_back(c.friction ? c.tangent_rate[k] : constant(0));
    for (const ContactRow& c : s_.contacts)
      for (int k = 0; k < 2; ++k) values.push_back(c.friction ? c.tangent_force[k] : constant(0));
    return values_at("CONTACT TANGENTS: each contact's sliding velocity along its two tangents, then each one's friction "
                     "along them (zeros without friction rows).",
                     "contact_tangents", "out", values, s_.for_tangents, "sliding velocities, then friction forces");
  }

  /// `void NAME(double t, const double* x, const double* yp, double* OUT)`:
  /// OUT[i] = values[i] at (t, y), after the assignments `slice` they need;
  /// owners[i], if given, the body values[i] is about and where it is declared.
  /// With `witness`, it calls witness_values() first (if written).
  CppFunction values_at(const char* doc, const char* name, const char* out, const std::vector<Expr>& values,
                        const std::vector<int>& slice, const char* comment,
                        const std::vector<std::pair<std::string, SourceLoc>>& owners = {}, bool witness = false,
                        const std::vector<std::string>& notes = {}) {
    CppFunction f{doc, fmt::format("void {}(double t, const double* {}, const double* yp, double* {}) override", name, s_.dae ? "y" : "x", out),
                  {CppStmt::line("(void)t;"), CppStmt::line(s_.dae ? "(void)y;" : "(void)x;"), CppStmt::line("(void)yp;")}};
    const Counting counting = count_into(f);
    std::vector<SectionResult> results;
    for (std::size_t i = 0; i < values.size(); ++i)
      results.push_back(i < owners.size() ? SectionResult{out, i, values[i], owners[i].first, owners[i].second, {}}
                                          : SectionResult{out, i, values[i], {}, {}, {}, i < notes.size() ? notes[i] : std::string{}});
    if (results.empty()) f.body.push_back(CppStmt::line(fmt::format("(void){};", out)));
    section(f.body, witness ? call_witness_values(f.body, slice) : slice, std::move(results), comment);
    return f;
  }

  /// Whether some state's nominal size is not 1 (reduce/nominal.hpp).
  bool any_nominal() const {
    return std::any_of(s_.nominal.begin(), s_.nominal.end(), [](const Expr& e) { return !is_one(e); });
  }

  void private_part(CppClass& c) {
    if (any_nominal())
      c.private_members.push_back(CppStmt::line(fmt::format("double nominal_[{}] = {{}};  // set in initial()", unknown_count())));
    if (has_rank_loss_) {
      c.public_methods.push_back({"Cut joints: the rows their multipliers' solves found dependent during the run.",
                                  "const mbgrt::RankLossLog* rank_loss() const override", {CppStmt::line("return &rank_loss_;")}});
      c.private_members.push_back(CppStmt::line("mbgrt::RankLossLog rank_loss_;  // what the rank-revealing solves found"));
    }
    if (!outline_.stores().empty()) {
      c.private_members.push_back(CppStmt::comment("equations computed by one function per shape (bodies, joints): what the rest reads of them"));
      for (CppStmt& st : outline_.stores()) c.private_members.push_back(std::move(st));
    }
    if (!witness_members_.empty()) {
      c.private_members.push_back(CppStmt::comment("witness_values(): what power() and stored_energy() read of it"));
      for (const std::string& m : witness_members_) c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;", m)));
    }
    // (a variable witness_values() keeps is its member in a long method's parts too)
    const std::unordered_set<std::string> kept(witness_members_.begin(), witness_members_.end());
    std::erase_if(scratch_, [&](const std::string& m) { return kept.count(m) > 0; });
    if (!scratch_.empty()) {
      c.private_members.push_back(CppStmt::comment("values one part of a long method passes to a later part"));
      for (const std::string& m : scratch_) c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;", m)));
    }
    if (!hoisted_order_.empty()) {
      c.private_members.push_back(CppStmt::comment("derived constants (set in initial())"));
      for (const Expr& e : hoisted_order_)
        c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;  // = {}", hoisted_.at(e), to_string(e, names_for_dump(g_)))));
    }
    if (!g_.params.empty()) {
      c.private_methods.push_back({"", "double param(std::size_t i, double model_value) const",
                                   {CppStmt::line("return overridden_[i] ? overrides_[i] : model_value;")}});
      c.private_members.push_back(CppStmt::comment("parameters (set in initial())"));
      Located located(*this, c.private_members);
      for (std::size_t i = 0; i < g_.params.size(); ++i) {
        const std::string at = located.head(g_.params[i].loc);
        c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;{}", names_.param(static_cast<int>(i)), at)));
      }
      c.private_members.push_back(CppStmt::line(fmt::format("std::array<double, {}> overrides_{{}};", g_.params.size())));
      c.private_members.push_back(CppStmt::line(fmt::format("std::array<bool, {}> overridden_{{}};", g_.params.size())));
    }
  }

  const ReducedSystem& s_;
  const BondGraph& g_;
  const SourceManager& sources_;
  const EmitOptions& opt_;
  Mangler mangle_;
  Namer names_;
  std::string class_name_;
  std::filesystem::path model_dir_;  // the directory of the model's file, as given (where() names files from it)
  int cse_counter_ = 0;
  std::map<std::string, Cost> costs_;  // method signature -> its cost
  Cost* cost_ = nullptr;               // the method being built
  std::string cost_signature_;         // its signature
  OutlineEmitter outline_;             // the shapes' functions and their runs' member arrays (codegen/outline_emit)
  std::unordered_map<int, std::string> discrete_name_;  // a contact's discrete variables -> their members
  ExprNames hoisted_;                // parameter expression -> member (codegen/derived_constants.hpp)
  std::vector<Expr> hoisted_order_;  // in first-use order
  bool has_rank_loss_ = false;        // a rank-revealing solve was written: the model keeps its log
  /// The dynamics are large enough to outline every section and repeat
  /// bodies (OutlineEmitter::measure_dynamics): the lists of initial(), of the
  /// parameters and of the unknowns are written compactly (they have
  /// thousands of entries).
  bool compact_ = false;
  std::vector<std::string> scratch_;  // members of split methods (codegen/split.hpp), in order of definition
  SharedValues witness_;                                // what witness_values() computes for power() and stored_energy()
  std::unordered_map<int, std::string> witness_names_;  // its exported variables -> their members or outlined places
  std::vector<std::string> witness_members_;            // the members of those not outlined, in order
  bool witness_active_ = false;                         // a caller's section is printed: witness_names_ name them
  Cost witness_cost_;                                   // the work of one call
  std::string witness_call_;                            // the call's statement
  /// Statements per part of a long method: g++ -O2 compiles the 100-rod
  /// chain's derivative (8,300 statements) in 20 s as one function. A cut
  /// costs run time (the parts share values through members): the 32-rod
  /// chain's derivative (about 3,900 statements) runs 5 % faster whole.
  static constexpr std::size_t kMaxMethodLines = 4000;
};

}  // namespace

std::string emit_cpp(const ReducedSystem& system, const SourceManager& sources, const EmitOptions& options,
                     EmitStats* stats) {
  Emitter e(system, sources, options);
  return e.run(stats);
}

std::size_t solve_linear_ops(std::size_t n) { return (4 * n * n * n + 9 * n * n - 7 * n) / 6; }

std::string namespace_problem(const std::string& name) {
  const bool identifier = !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0])) &&
                          std::all_of(name.begin(), name.end(), [](char c) {
                            return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                          });
  if (!identifier) return "`" + name + "` is not a C++ identifier (letters, digits and _, not starting with a digit)";
  if (name != "mbgc_model" && reserved(name))
    return "`" + name + "` is reserved in the generated C++ (a keyword, a standard macro or a name the class uses)";
  return {};
}

}  // namespace mbgc::codegen
