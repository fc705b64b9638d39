#include "codegen/emit_cpp.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <set>
#include <stdexcept>

#include "codegen/cpp.hpp"
#include "codegen/split.hpp"
#include "codegen/template.hpp"

namespace mbgc::codegen {
namespace {

using namespace mbgc::ir;

// Identifiers a model name must not become: C++ keywords and alternative
// tokens, macros the included headers define, and the names the generated
// class itself uses (its methods, locals and members).
const std::set<std::string> kReserved = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case",
    "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept", "const", "consteval",
    "constexpr", "constinit", "const_cast", "continue", "co_await", "co_return", "co_yield", "decltype",
    "default", "delete", "do", "double", "dynamic_cast", "else", "enum", "explicit", "export", "extern",
    "false", "float", "for", "friend", "goto", "if", "inline", "int", "long", "mutable", "namespace",
    "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq", "private", "protected",
    "public", "register", "reinterpret_cast", "requires", "return", "short", "signed", "sizeof",
    "static", "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local",
    "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual",
    "void", "volatile", "wchar_t", "while", "xor", "xor_eq", "final", "override", "import", "module",
    // macros from <cmath>, <climits>, <cstddef>, <cstdio> and friends
    "NAN", "INFINITY", "HUGE_VAL", "HUGE_VALF", "HUGE_VALL", "NULL", "EOF", "errno", "assert",
    "offsetof", "math_errhandling", "MATH_ERRNO", "MATH_ERREXCEPT", "DOMAIN", "SING", "OVERFLOW",
    "UNDERFLOW", "TLOSS", "PLOSS", "CHAR_BIT", "INT_MAX", "INT_MIN", "stdin", "stdout", "stderr",
    "unix", "linux", "i386",
    // names the generated code uses itself
    "t", "x", "xdot", "xp", "y", "yp", "r", "jac_out", "rows_out", "out", "id", "i", "s", "value", "std", "mbgrt", "mbgc_model",
    "main", "model", "argc", "argv", "param", "overrides_", "overridden_", "kNames", "kParams",
    "name", "source_file", "size", "variable_name", "output_names", "parameters", "is_dae",
    "differential_ids", "default_settings", "set_parameter", "initial", "derivative", "residual",
    "outputs", "terminal", "state_count", "position_constraint_count", "velocity_constraint_count",
    "constraints_enforced", "constraint_name", "constraints", "kConstraintNames", "jacobian", "has_jacobian", "state_limit", "state_limit_reason"};

/// Reserved by the C++ implementation or by the standard library's macros.
bool reserved(const std::string& id) {
  if (kReserved.count(id)) return true;
  if (id.size() > 1 && id[0] == '_' && (std::isupper(static_cast<unsigned char>(id[1])) || id[1] == '_')) return true;
  if (id.find("__") != std::string::npos) return true;
  // <cmath>/<cfloat>/<cstdint> macro families: M_PI, FP_NAN, DBL_MAX, INT8_MAX, ...
  for (const char* prefix : {"M_", "FP_", "DBL_", "FLT_", "LDBL_", "INT", "UINT", "SIZE_", "PTRDIFF_"})
    if (id.rfind(prefix, 0) == 0 && std::all_of(id.begin(), id.end(), [](char c) {
          return std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_';
        }))
      return true;
  return false;
}

/// Unique C++ identifiers for model names ("m1.rotor.p" -> "m1_rotor_p").
class Mangler {
 public:
  std::string get(const std::string& key, const std::string& model_name) {
    if (auto it = given_.find(key); it != given_.end()) return it->second;
    std::string id;
    for (char c : model_name) {
      bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_';
      if (ok) id += c;
      else if (!id.empty() && id.back() != '_') id += '_';
    }
    while (!id.empty() && id.back() == '_') id.pop_back();
    while (!id.empty() && id.front() == '_') id.erase(id.begin());
    for (auto p = id.find("__"); p != std::string::npos; p = id.find("__")) id.erase(p, 1);
    if (id.empty() || std::isdigit(static_cast<unsigned char>(id[0]))) id = "v_" + id;
    if (id.rfind("cse", 0) == 0) id = "v_" + id;  // keep cseN for common subexpressions
    if (reserved(id)) id += "_v";  // lower-case suffix: no longer a keyword or a macro-like name
    std::string unique = id;
    for (int k = 2; used_.count(unique); ++k) unique = fmt::format("{}_{}", id, k);
    used_.insert(unique);
    given_[key] = unique;
    return unique;
  }

 private:
  std::map<std::string, std::string> given_;
  std::set<std::string> used_;
};

std::string cpp_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string cpp_double(double v) {
  if (std::isnan(v)) return "std::numeric_limits<double>::quiet_NaN()";
  if (std::isinf(v)) return v > 0 ? "std::numeric_limits<double>::infinity()" : "-std::numeric_limits<double>::infinity()";
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

class Emitter {
 public:
  Emitter(const ReducedSystem& sys, const SourceManager& sources, const EmitOptions& opt)
      : s_(sys), g_(sys.graph), sources_(sources), opt_(opt) {
    // fmt::format, not "p" + std::to_string(i): GCC 12 at -O3 reports a false
    // -Wrestrict on operator+(const char*, std::string&&) (GCC PR 105329).
    for (std::size_t i = 0; i < g_.params.size(); ++i) mangle_.get(fmt::format("p{}", i), g_.params[i].name);
    for (std::size_t i = 0; i < g_.vars.size(); ++i) mangle_.get(fmt::format("v{}", i), g_.vars[i].name);
    names_.var = [this](int id) { return mangle_.get(fmt::format("v{}", id), ""); };
    names_.param = [this](int id) { return mangle_.get(fmt::format("p{}", id), ""); };
    class_name_ = mangle_.get("class", g_.model_name + "_model");
  }

  std::string run(EmitStats* stats) {
    CppClass c;
    c.name = class_name_;
    c.base = "mbgrt::Model";
    identity(c);
    find_parameter_expressions();
    c.public_methods.push_back(initial());
    add_long_method(c, s_.dae ? residual() : derivative());
    if (!s_.jacobian.empty()) {
      c.public_methods.push_back({"", "bool has_jacobian() const override", {CppStmt::line("return true;")}});
      add_long_method(c, jacobian());
    }
    c.public_methods.push_back(outputs());
    if (!s_.constraints.empty()) constraint_functions(c);
    c.public_methods.push_back({"TERMINAL: nothing to do at the end of a run.",
                                "void terminal(double t, const double* y) override", {CppStmt::line("(void)t;"), CppStmt::line("(void)y;")}});
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
      entry = fmt::format("int main(int argc, char** argv) {{\n  {} model;\n  return mbgrt::run_main(model, argc, argv);\n}}\n", class_name_);
    }
    std::string out = kSimulatorTemplate;
    replace(out, "{{banner}}", banner);
    replace(out, "{{model_class}}", body);
    replace(out, "{{entry_point}}", entry);
    // No trailing blank lines: one newline at the end.
    while (out.size() > 1 && out[out.size() - 1] == '\n' && out[out.size() - 2] == '\n') out.pop_back();
    if (stats) collect_stats(c, out, *stats);
    return out;
  }

  /// A method that may be long (the dynamics, the Jacobian): past
  /// kMaxMethodLines statements it is cut into parts (codegen/split.hpp).
  void add_long_method(CppClass& c, CppFunction f) {
    auto split = split_method(f, kMaxMethodLines);
    if (!split) {
      c.public_methods.push_back(std::move(f));
      return;
    }
    c.public_methods.push_back(std::move(split->method));
    for (CppFunction& part : split->parts) c.private_methods.push_back(std::move(part));
    for (std::string& m : split->members)
      if (std::find(scratch_.begin(), scratch_.end(), m) == scratch_.end()) scratch_.push_back(std::move(m));
  }

  /// The costs counted while the methods were built, with their size in the file.
  void collect_stats(const CppClass& c, const std::string& out, EmitStats& stats) const {
    stats = {};
    stats.model = g_.model_name;
    stats.dae = s_.dae;
    stats.states = s_.states.size();
    stats.algebraic = s_.algebraic.size();
    // both forms print the class inside a namespace, its methods two levels in
    const int indent = 2;
    for (const auto* methods : {&c.public_methods, &c.private_methods})
      for (const CppFunction& f : *methods) {
        FunctionStats fs;
        const std::string& sig = f.signature;
        auto open = sig.find('(');
        auto start = sig.find_last_of(' ', open);
        fs.name = sig.substr(start == std::string::npos ? 0 : start + 1, open - (start == std::string::npos ? 0 : start + 1));
        std::string text = print(f, indent);
        fs.bytes = text.size();
        fs.lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
        if (auto it = costs_.find(sig); it != costs_.end()) {
          fs.ops = it->second.ops;
          fs.solves = it->second.solves;
          for (std::size_t n : fs.solves) fs.solve_ops += solve_linear_ops(n);
        }
        stats.functions.push_back(std::move(fs));
      }
    // A long method's parts (NAME_partK) count as lines and bytes of NAME.
    for (auto it = stats.functions.begin(); it != stats.functions.end();) {
      const auto cut = it->name.rfind("_part");
      auto base = cut == std::string::npos ? stats.functions.end()
                                           : std::find_if(stats.functions.begin(), stats.functions.end(),
                                                          [&](const FunctionStats& g) { return g.name == it->name.substr(0, cut); });
      if (base == stats.functions.end()) {
        ++it;
        continue;
      }
      base->lines += it->lines;
      base->bytes += it->bytes;
      it = stats.functions.erase(it);
    }
    stats.file_bytes = out.size();
    stats.file_lines = static_cast<std::size_t>(std::count(out.begin(), out.end(), '\n'));
  }

  /// What a method's expressions and linear solves cost, counted as they are printed.
  struct Cost {
    CppOps ops;
    std::vector<std::size_t> solves;
  };
  /// While the returned guard lives, printed expressions count towards method `f`.
  struct Counting {
    Cost*& cost;
    ~Counting() { cost = nullptr; }
  };
  [[nodiscard]] Counting count_into(const CppFunction& f) {
    cost_ = &costs_[f.signature];
    return Counting{cost_};
  }

 private:
  static void replace(std::string& s, const std::string& key, const std::string& value) {
    auto pos = s.find(key);
    if (pos != std::string::npos) s.replace(pos, key.size(), value);
  }

  std::string where(const SourceLoc& loc) const {
    if (!loc.valid()) return "(generated)";
    return fmt::format("{}:{}:{}", sources_.file(loc.file).display_path, loc.line, loc.col);
  }

  std::string var_name(int id) const { return names_.var(id); }

  /// Bounds beyond which a state's model no longer holds (a beam's modal
  /// coordinates): the runtime stops the run there and prints the reason.
  void state_limits(CppClass& c) {
    std::vector<std::string> bounds, reasons;
    for (std::size_t i = 0; i < s_.states.size(); ++i) {
      const GraphNode& nd = g_.nodes[static_cast<std::size_t>(s_.states[i].node)];
      const auto& vars = nd.state_vars;
      auto k = static_cast<std::size_t>(std::find(vars.begin(), vars.end(), s_.states[i].var) - vars.begin());
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

  std::size_t unknown_count() const { return s_.states.size() + s_.algebraic.size(); }

  // ---- identity and metadata -----------------------------------------------------------
  void identity(CppClass& c) {
    c.public_methods.push_back({"", "const char* name() const override", {CppStmt::line(fmt::format("return {};", cpp_string(g_.model_name)))}});
    c.public_methods.push_back({"", "const char* source_file() const override", {CppStmt::line(fmt::format("return {};", cpp_string(opt_.source_display)))}});
    c.public_methods.push_back({"", "std::size_t size() const override", {CppStmt::line(fmt::format("return {};", unknown_count()))}});
    std::vector<std::string> unknown_names;
    for (const StateVar& st : s_.states) unknown_names.push_back(cpp_string(g_.vars[static_cast<std::size_t>(st.var)].name));
    for (int a : s_.algebraic) unknown_names.push_back(cpp_string(g_.vars[static_cast<std::size_t>(a)].name));
    CppFunction vn{"", "std::string variable_name(std::size_t i) const override", {}};
    if (unknown_names.empty()) {
      vn.body.push_back(CppStmt::line("(void)i;"));
      vn.body.push_back(CppStmt::line("return \"?\";"));
    } else {
      vn.body.push_back(CppStmt::line(fmt::format("static const char* const kNames[] = {{{}}};", fmt::join(unknown_names, ", "))));
      vn.body.push_back(CppStmt::line(fmt::format("return i < {} ? kNames[i] : \"?\";", unknown_names.size())));
    }
    c.public_methods.push_back(vn);
    state_limits(c);
    std::vector<std::string> outs;
    for (const Output& o : g_.outputs) outs.push_back(cpp_string(o.name));
    c.public_methods.push_back({"", "std::vector<std::string> output_names() const override",
                                {CppStmt::line(fmt::format("return {{{}}};", fmt::join(outs, ", ")))}});
    CppFunction params{"", "std::vector<mbgrt::ParameterInfo> parameters() const override", {}};
    std::vector<std::string> infos;
    for (const Parameter& p : g_.params)
      infos.push_back(fmt::format("{{{}, {}, {}}}", cpp_string(p.name),
                                  p.literal ? cpp_double(p.literal_value) : "std::numeric_limits<double>::quiet_NaN()",
                                  cpp_string(p.literal ? "" : computed_doc(p))));
    if (infos.empty()) params.body.push_back(CppStmt::line("return {};"));
    else {
      params.body.push_back(CppStmt::line("return {"));
      for (const std::string& s : infos) params.body.push_back(CppStmt::line("    " + s + ","));
      params.body.push_back(CppStmt::line("};"));
    }
    c.public_methods.push_back(params);
    if (s_.dae) {
      CppFunction ids{"", "void differential_ids(double* id) const override", {}};
      for (std::size_t i = 0; i < unknown_count(); ++i)
        ids.body.push_back(CppStmt::line(fmt::format("id[{}] = {};", i, i < s_.states.size() ? "1.0" : "0.0")));
      c.public_methods.push_back(ids);
      c.public_methods.push_back({"", "bool is_dae() const override", {CppStmt::line("return true;")}});
    }
    CppFunction settings{"Defaults from the model's simulate { } block; the command line overrides them.",
                         "mbgrt::Settings default_settings() const override", {CppStmt::line("mbgrt::Settings s;")}};
    const SimSettings& ss = g_.settings;
    if (ss.t_end) settings.body.push_back(CppStmt::line(fmt::format("s.t_end_s = {};", cpp_double(*ss.t_end))));
    if (ss.interval) settings.body.push_back(CppStmt::line(fmt::format("s.interval_s = {};", cpp_double(*ss.interval))));
    std::string solver = ss.solver.value_or(s_.dae ? "ida" : "cvode");
    settings.body.push_back(CppStmt::line(fmt::format("s.solver = mbgrt::Solver::{};", solver)));
    if (ss.rtol) settings.body.push_back(CppStmt::line(fmt::format("s.rtol = {};", cpp_double(*ss.rtol))));
    if (ss.atol) settings.body.push_back(CppStmt::line(fmt::format("s.atol = {};", cpp_double(*ss.atol))));
    if (ss.step) settings.body.push_back(CppStmt::line(fmt::format("s.step_s = {};", cpp_double(*ss.step))));
    settings.body.push_back(CppStmt::line("return s;"));
    c.public_methods.push_back(settings);
    CppFunction set{"", "bool set_parameter(const std::string& name, double value) override", {}};
    if (g_.params.empty()) {
      set.body.push_back(CppStmt::line("(void)name;"));
      set.body.push_back(CppStmt::line("(void)value;"));
      set.body.push_back(CppStmt::line("return false;"));
    } else {
      std::vector<std::string> pn;
      for (const Parameter& p : g_.params) pn.push_back(cpp_string(p.name));
      set.body.push_back(CppStmt::line(fmt::format("static const char* const kParams[] = {{{}}};", fmt::join(pn, ", "))));
      set.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = 0; i < {}; ++i) {{", g_.params.size())));
      set.body.push_back(CppStmt::line("  if (name != kParams[i]) continue;"));
      set.body.push_back(CppStmt::line("  overrides_[i] = value;"));
      set.body.push_back(CppStmt::line("  overridden_[i] = true;"));
      set.body.push_back(CppStmt::line("  return true;"));
      set.body.push_back(CppStmt::line("}"));
      set.body.push_back(CppStmt::line("return false;"));
    }
    c.public_methods.push_back(set);
  }

  /// "= FORMULA" of a computed parameter (sim --list-parameters prints it); a
  /// long one (a joint frame from its axis) as the parameters it is computed from.
  std::string computed_doc(const Parameter& p) const {
    // Every node prints at least one character: past 80 nodes, no need to print it.
    if (ir::size(p.value) <= 80) {
      std::string formula = to_string(p.value, names_for_dump());
      if (formula.size() <= 80) return "= " + formula;
    }
    std::unordered_set<int> ids;
    collect_params(p.value, ids);
    std::vector<int> order(ids.begin(), ids.end());
    std::sort(order.begin(), order.end());
    std::vector<std::string> from;
    for (int id : order) {
      const std::string& full = g_.params[static_cast<std::size_t>(id)].name;
      std::string base = full.substr(0, full.find('['));  // link.axis_a[2] -> link.axis_a
      if (std::find(from.begin(), from.end(), base) == from.end()) from.push_back(base);
    }
    if (from.empty()) return "= a long constant expression";
    return fmt::format("= a function of {}", fmt::join(from, ", "));
  }

  Namer names_for_dump() const {
    Namer n;
    n.var = [this](int id) { return g_.vars[static_cast<std::size_t>(id)].name; };
    n.param = [this](int id) { return g_.params[static_cast<std::size_t>(id)].name; };
    return n;
  }

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
    // chain) repeat subexpressions: share them here too. A parameter only
    // reads earlier ones, so a temporary defined before its first use reads
    // parameters that are already set (overrides included).
    const std::unordered_map<Expr, std::string, ExprHash, ExprEqual> none;
    SharedTemps shared(none);
    for (const Parameter& p : g_.params) shared.count(p.value);
    for (const Expr& e : hoisted_order_) shared.count(e);
    for (const StateVar& st : s_.states) shared.count(st.initial);
    shared.finish_counting();
    for (std::size_t i = 0; i < g_.params.size(); ++i) {
      const Parameter& p = g_.params[i];
      std::string value = print_shared(p.value, shared, f.body);
      f.body.push_back(CppStmt::line(fmt::format("{} = param({}, {});  // {}", names_.param(static_cast<int>(i)), i,
                                                 value, where(p.loc))));
    }
    if (!hoisted_order_.empty()) f.body.push_back(CppStmt::comment("DERIVED CONSTANTS: parameter expressions, computed once per run"));
    for (const Expr& e : hoisted_order_) {
      // a derived constant that recurs whole is reused by its own name
      bool shared_whole = shared.pending.erase(e) > 0;
      std::string value = print_shared(e, shared, f.body);
      f.body.push_back(CppStmt::line(fmt::format("{} = {};", hoisted_.at(e), value)));
      if (shared_whole) shared.temp[e] = hoisted_.at(e);
    }
    if (!s_.states.empty()) f.body.push_back(CppStmt::comment("INITIAL STATE"));
    const char* y = s_.dae ? "y" : "x";
    for (std::size_t i = 0; i < s_.states.size(); ++i) {
      const StateVar& st = s_.states[i];
      const Variable& v = g_.vars[static_cast<std::size_t>(st.var)];
      std::string value = print_shared(st.initial, shared, f.body);
      f.body.push_back(CppStmt::line(fmt::format("{}[{}] = {};  // {} ({})", y, i, value, v.name, where(v.loc))));
    }
    if (s_.dae) {
      for (std::size_t j = 0; j < s_.algebraic.size(); ++j)
        f.body.push_back(CppStmt::line(fmt::format("y[{}] = 0.0;  // {}: first guess, made consistent by IDA", s_.states.size() + j,
                                                   g_.vars[static_cast<std::size_t>(s_.algebraic[j])].name)));
      f.body.push_back(CppStmt::line(fmt::format("for (std::size_t i = 0; i < {}; ++i) yp[i] = 0.0;  // first guess", unknown_count())));
    }
    return f;
  }

  // ---- common subexpressions -------------------------------------------------------------
  /// Subexpressions used more than once in one function, defined as `const
  /// double cseN` right before their first use. `temp` starts with the
  /// derived constants, which are members already.
  struct SharedTemps {
    explicit SharedTemps(const std::unordered_map<Expr, std::string, ExprHash, ExprEqual>& known)
        : known_(known), temp(known.begin(), known.end()) {}
    void count(const Expr& e) {
      if (e->args.empty() || (e->op == Op::Neg && e->args[0]->args.empty())) return;
      if (known_.count(e)) return;  // computed once in initial()
      if (++uses_[e] > 1) return;   // children already counted through the first occurrence
      for (const Expr& a : e->args) count(a);
    }
    void finish_counting() {
      for (const auto& [e, n] : uses_)
        if (n > 1) pending.insert(e);
      uses_.clear();
    }
    const std::unordered_map<Expr, std::string, ExprHash, ExprEqual>& known_;
    std::unordered_map<Expr, int, ExprHash, ExprEqual> uses_;
    std::unordered_map<Expr, std::string, ExprHash, ExprEqual> temp;
    std::unordered_set<Expr, ExprHash, ExprEqual> pending;
    bool announced = false;  // the note on cseN names is printed
  };

  /// `e` in C++, after defining (into `body`) the shared temporaries it needs, innermost first.
  std::string print_shared(const Expr& e, SharedTemps& shared, std::vector<CppStmt>& body) {
    std::unordered_set<const Node*> seen;
    std::function<void(const Expr&)> define = [&](const Expr& x) {
      if (x->args.empty() || !seen.insert(x.get()).second) return;
      // A temporary named after its whole sub-tree was walked defines nothing new below.
      if (!shared.known_.count(x) && shared.temp.count(x)) return;
      for (const Expr& a : x->args) define(a);
      if (shared.pending.count(x) && !shared.temp.count(x)) {
        std::string name = fmt::format("cse{}", ++cse_counter_);
        if (!shared.announced) body.push_back(CppStmt::comment("(cseN: a subexpression several equations below share)"));
        shared.announced = true;
        body.push_back(CppStmt::line(fmt::format("const double {} = {};", name, cpp_with_temps(x, shared.temp, /*top=*/true))));
        shared.temp[x] = name;
      }
    };
    define(e);
    return cpp_with_temps(e, shared.temp, false);
  }

  // ---- sections with equations ------------------------------------------------------------
  /// Read the unknowns a section uses, compute its assignments, then its results.
  void section(std::vector<CppStmt>& body, const std::vector<int>& assignment_indices,
               const std::vector<std::pair<std::string, Expr>>& results, const std::string& results_comment) {
    // Which variables does this section touch?
    std::unordered_set<int> used;
    std::set<int> blocks_read;  // a block's unknowns share its inputs: read them once
    for (int i : assignment_indices) {
      const Assignment& a = s_.assignments[static_cast<std::size_t>(i)];
      if (a.block >= 0 && !blocks_read.insert(a.block).second) continue;
      assignment_inputs(s_, a, used);
    }
    for (const auto& [target, e] : results) collect_vars(e, used);
    const char* y = s_.dae ? "y" : "x";
    bool any_read = false;
    for (std::size_t i = 0; i < s_.states.size(); ++i) {
      int v = s_.states[i].var;
      if (!used.count(v)) continue;
      if (!any_read) body.push_back(CppStmt::comment(s_.dae ? "unknowns from the integrator" : "states"));
      any_read = true;
      body.push_back(CppStmt::line(fmt::format("const double {} = {}[{}];", var_name(v), y, i)));
    }
    for (std::size_t j = 0; j < s_.algebraic.size(); ++j) {
      int v = s_.algebraic[j];
      if (!used.count(v)) continue;
      body.push_back(CppStmt::line(fmt::format("const double {} = y[{}];", var_name(v), s_.states.size() + j)));
    }
    for (std::size_t i = 0; i < s_.derivative_unknowns.size(); ++i) {
      int v = s_.derivative_unknowns[i];
      if (v < 0 || !used.count(v)) continue;
      body.push_back(CppStmt::line(fmt::format("const double {} = yp[{}];", var_name(v), i)));
    }
    // Common subexpressions: anything non-trivial used twice or more in this section.
    SharedTemps shared(hoisted_);
    auto visit = [&](const Expr& e) { shared.count(e); };
    std::set<int> blocks_counted;
    for (int i : assignment_indices) {
      const Assignment& a = s_.assignments[static_cast<std::size_t>(i)];
      if (a.block < 0) {
        visit(a.value);
        continue;
      }
      if (!blocks_counted.insert(a.block).second) continue;  // count each block once
      const LinearBlock& lb = s_.linear_blocks[static_cast<std::size_t>(a.block)];
      for (const Expr& e : lb.a) visit(e);
      for (const Expr& e : lb.b) visit(e);
    }
    for (const auto& [target, e] : results) visit(e);
    shared.finish_counting();
    auto& pending = shared.pending;
    auto& temp = shared.temp;
    auto print_expr = [&](const Expr& e, std::vector<CppStmt>& out_body) { return print_shared(e, shared, out_body); };
    std::set<int> blocks_done;
    std::string last_origin;
    for (int i : assignment_indices) {
      const Assignment& a = s_.assignments[static_cast<std::size_t>(i)];
      if (a.block >= 0) {
        if (blocks_done.insert(a.block).second) emit_block(body, a, print_expr);
        body.push_back(CppStmt::line(fmt::format("const double {} = blk{}_x[{}];", var_name(a.var), a.block + 1, block_position(a))));
        continue;
      }
      // One comment heads each run of assignments from the same model line and origin.
      std::string origin = fmt::format("{}  {}", where(a.loc), a.origin);
      if (origin != last_origin) body.push_back(CppStmt::comment(origin));
      last_origin = std::move(origin);
      // An assignment whose whole value recurs elsewhere becomes the shared
      // name itself: `hub_f = hub_p / J_hub`, reused, rather than a cseN copy.
      bool shared_whole = pending.count(a.value) && !temp.count(a.value);
      if (shared_whole) pending.erase(a.value);
      std::string rhs = print_expr(a.value, body);
      body.push_back(CppStmt::line(fmt::format("const double {} = {};", var_name(a.var), rhs)));
      if (shared_whole) temp[a.value] = var_name(a.var);
    }
    if (!results.empty()) body.push_back(CppStmt::comment(results_comment));
    for (const auto& [target, e] : results) {
      std::string rhs = print_expr(e, body);
      body.push_back(CppStmt::line(fmt::format("{} = {};", target, rhs)));
    }
  }

  std::size_t block_position(const Assignment& a) const {
    const LinearBlock& lb = s_.linear_blocks[static_cast<std::size_t>(a.block)];
    return static_cast<std::size_t>(std::find(lb.unknowns.begin(), lb.unknowns.end(), a.var) - lb.unknowns.begin());
  }

  /// A numerically solved loop: fill A and b, solve in place.
  template <class Print>
  void emit_block(std::vector<CppStmt>& body, const Assignment& a, Print& print_expr) {
    const LinearBlock& lb = s_.linear_blocks[static_cast<std::size_t>(a.block)];
    std::size_t n = lb.unknowns.size();
    std::vector<std::string> names;
    for (int u : lb.unknowns) names.push_back(g_.vars[static_cast<std::size_t>(u)].name);
    body.push_back(CppStmt::comment(fmt::format("{}  {}", where(a.loc), a.origin)));
    body.push_back(CppStmt::comment(fmt::format("A x = b for x = ({})", fmt::join(names, ", "))));
    std::vector<std::string> entries, rhs;
    for (const Expr& e : lb.a) entries.push_back(print_expr(e, body));
    for (const Expr& e : lb.b) rhs.push_back(print_expr(e, body));
    std::string id = fmt::format("blk{}", a.block + 1);
    body.push_back(CppStmt::line(fmt::format("double {}_a[{}] = {{", id, n * n)));
    for (std::size_t r = 0; r < n; ++r) {
      std::vector<std::string> row(entries.begin() + static_cast<long>(r * n), entries.begin() + static_cast<long>((r + 1) * n));
      body.push_back(CppStmt::line(fmt::format("    {},", fmt::join(row, ", "))));
    }
    body.push_back(CppStmt::line("};"));
    body.push_back(CppStmt::line(fmt::format("double {}_x[{}] = {{{}}};", id, n, fmt::join(rhs, ", "))));
    body.push_back(CppStmt::line(fmt::format("mbgrt::{}({}, {}_a, {}_x);", lb.rank_revealing ? "solve_rank_revealing" : "solve_linear", n, id, id)));
    if (!cost_) throw std::logic_error("mbgc: a linear solve outside a counted method (codegen bug)");
    cost_->solves.push_back(n);
  }

  /// Where the operations of printed text go: the method being built.
  CppOps* ops() {
    if (!cost_) throw std::logic_error("mbgc: an expression printed outside a counted method (codegen bug)");
    return &cost_->ops;
  }

  /// to_cpp, with already-defined common subexpressions replaced by their names.
  std::string cpp_with_temps(const Expr& e, const std::unordered_map<Expr, std::string, ExprHash, ExprEqual>& temp, bool top) {
    if (temp.empty()) return to_cpp(e, names_, ops());
    // Each defined temporary prints as its name, as a variable would; with
    // `top`, e itself is written out (its definition).
    const NamedNodes named = [&](const Expr& x) -> const std::string* {
      if (top && x.get() == e.get()) return nullptr;
      auto it = temp.find(x);
      return it == temp.end() ? nullptr : &it->second;
    };
    return to_cpp(e, names_, named, ops());
  }

  CppFunction derivative() {
    CppFunction f{"DERIVATIVE: the state derivatives, in causal order.",
                  "void derivative(double t, const double* x, double* xdot) override", {CppStmt::line("(void)t;"), CppStmt::line("(void)x;")}};
    const Counting counting = count_into(f);
    std::vector<std::pair<std::string, Expr>> results;
    for (std::size_t i = 0; i < s_.states.size(); ++i)
      results.push_back({fmt::format("xdot[{}]", i), s_.state_derivative[i]});
    if (results.empty()) f.body.push_back(CppStmt::line("(void)xdot;"));
    section(f.body, s_.for_derivative, results, "state derivatives");
    return f;
  }

  CppFunction jacobian() {
    std::size_t n = s_.states.size();
    CppFunction f{"JACOBIAN: d xdot_i / d x_j (row-major), derived symbolically, for the implicit solvers.",
                  "void jacobian(double t, const double* x, double* jac_out) override",
                  {CppStmt::line("(void)t;"), CppStmt::line("(void)x;"),
                   CppStmt::line(fmt::format("for (std::size_t k = 0; k < {}; ++k) jac_out[k] = 0.0;", n * n))}};
    const Counting counting = count_into(f);
    std::vector<std::pair<std::string, Expr>> results;
    for (std::size_t k = 0; k < s_.jacobian.size(); ++k)
      if (!is_zero(s_.jacobian[k])) results.push_back({fmt::format("jac_out[{}]", k), s_.jacobian[k]});
    section(f.body, s_.for_jacobian, results, "nonzero entries");
    return f;
  }

  CppFunction residual() {
    CppFunction f{"RESIDUAL (DAE): r = F(t, y, yp) must vanish; states first, then algebraic unknowns.",
                  "void residual(double t, const double* y, const double* yp, double* r) override",
                  {CppStmt::line("(void)t;"), CppStmt::line("(void)y;"), CppStmt::line("(void)yp;")}};
    const Counting counting = count_into(f);
    std::vector<std::pair<std::string, Expr>> results;
    for (std::size_t i = 0; i < s_.residuals.size(); ++i)
      results.push_back({fmt::format("r[{}]", i), s_.residuals[i].value});
    section(f.body, s_.for_derivative, results, "residuals");
    return f;
  }

  /// The CN rows for assembly and drift reports: g (position level) for every
  /// row, then gdot (velocity level) for every row.
  void constraint_functions(CppClass& c) {
    std::size_t n = s_.constraints.size();
    // A model may mix strategies per joint: any lagrange row makes it a DAE
    // whose drift is what the runtime reports.
    bool enforced = std::any_of(s_.constraints.begin(), s_.constraints.end(),
                                [](const ConstraintRow& r) { return r.multiplier >= 0; });
    if (s_.dae)
      c.public_methods.push_back({"", "std::size_t state_count() const override", {CppStmt::line(fmt::format("return {};", s_.states.size()))}});
    c.public_methods.push_back({"", "std::size_t position_constraint_count() const override", {CppStmt::line(fmt::format("return {};", n))}});
    c.public_methods.push_back({"", "std::size_t velocity_constraint_count() const override", {CppStmt::line(fmt::format("return {};", n))}});
    c.public_methods.push_back({enforced ? "lagrange: the DAE enforces the constraints; the runtime reports their drift."
                                         : "penalty: the constraints are only pulled back; the runtime reports the violation.",
                                "bool constraints_enforced() const override", {CppStmt::line(enforced ? "return true;" : "return false;")}});
    CppFunction names{"", "std::string constraint_name(std::size_t i) const override", {}};
    std::vector<std::string> list;
    for (const ConstraintRow& r : s_.constraints) list.push_back(cpp_string(r.name + " g"));
    for (const ConstraintRow& r : s_.constraints) list.push_back(cpp_string(r.name + " gdot"));
    names.body.push_back(CppStmt::line(fmt::format("static const char* const kConstraintNames[] = {{{}}};", fmt::join(list, ", "))));
    names.body.push_back(CppStmt::line(fmt::format("return i < {} ? kConstraintNames[i] : \"?\";", 2 * n)));
    c.public_methods.push_back(names);
    if (s_.dae) multiplier_indices(c);
    const char* y = s_.dae ? "y" : "x";
    CppFunction f{"CONSTRAINTS: g(x) for every CN row, then gdot(x).",
                  fmt::format("void constraints(double t, const double* {}, double* rows_out) override", y),
                  {CppStmt::line("(void)t;"), CppStmt::line(fmt::format("(void){};", y))}};
    const Counting counting = count_into(f);
    std::vector<std::pair<std::string, Expr>> results;
    for (std::size_t i = 0; i < n; ++i) results.push_back({fmt::format("rows_out[{}]", i), s_.constraints[i].g});
    for (std::size_t i = 0; i < n; ++i) results.push_back({fmt::format("rows_out[{}]", n + i), s_.constraints[i].gdot});
    section(f.body, s_.for_constraints, results, "g, then gdot");
    c.public_methods.push_back(f);
  }

  /// Where each CN row's multipliers sit in y (lagrange rows; -1 for penalty
  /// rows): lambda (its residual row is gdot = 0) and the GGL mu (g = 0). The
  /// runtime needs them to hold the multipliers of redundant rows at zero.
  void multiplier_indices(CppClass& c) {
    std::map<int, std::size_t> index_of;
    for (std::size_t i = 0; i < s_.algebraic.size(); ++i) index_of[s_.algebraic[i]] = s_.states.size() + i;
    auto table = [&](const char* method, const char* doc, auto member) {
      std::vector<std::string> list;
      for (const ConstraintRow& r : s_.constraints) {
        auto it = index_of.find(r.*member);
        list.push_back(it == index_of.end() ? "-1" : std::to_string(it->second));
      }
      c.public_methods.push_back(
          {doc, fmt::format("long {}(std::size_t row) const override", method),
           {CppStmt::line(fmt::format("static const long kIndex[] = {{{}}};", fmt::join(list, ", "))),
            CppStmt::line(fmt::format("return row < {} ? kIndex[row] : -1;", list.size()))}});
    };
    table("multiplier_index", "index in y of CN row `row`'s multiplier lambda (-1: penalty row)", &ConstraintRow::multiplier);
    table("stabiliser_index", "index in y of CN row `row`'s GGL multiplier mu (-1: penalty row)", &ConstraintRow::stabiliser);
  }

  CppFunction outputs() {
    CppFunction f{"OUTPUT: the declared outputs at (t, y).",
                  fmt::format("void outputs(double t, const double* {}, const double* yp, double* out) override", s_.dae ? "y" : "x"),
                  {CppStmt::line("(void)t;"), CppStmt::line(s_.dae ? "(void)y;" : "(void)x;"), CppStmt::line("(void)yp;")}};
    const Counting counting = count_into(f);
    std::vector<std::pair<std::string, Expr>> results;
    for (std::size_t i = 0; i < g_.outputs.size(); ++i) results.push_back({fmt::format("out[{}]", i), g_.outputs[i].value});
    if (results.empty()) f.body.push_back(CppStmt::line("(void)out;"));
    section(f.body, s_.for_outputs, results, "outputs, in declaration order");
    return f;
  }

  /// Largest subexpressions that depend on parameters only (1/J, m*g, ...):
  /// they are computed once in initial() instead of at every derivative call.
  void find_parameter_expressions() {
    // Expressions are DAGs (derivatives and torn loops share sub-trees):
    // every walk here remembers the nodes it has seen.
    std::unordered_map<const Node*, bool> param_memo, costly_memo;
    std::function<bool(const Expr&)> param_only = [&](const Expr& e) {
      if (auto it = param_memo.find(e.get()); it != param_memo.end()) return it->second;
      bool r = !(e->op == Op::Var || e->op == Op::Time || e->op == Op::Der);
      for (const Expr& a : e->args)
        if (r && !param_only(a)) r = false;
      return param_memo[e.get()] = r;
    };
    // Only what costs something at run time (a division, a power, a function
    // call) is worth a member: -m * g reads better where it is used.
    std::function<bool(const Expr&)> costly = [&](const Expr& e) {
      if (auto it = costly_memo.find(e.get()); it != costly_memo.end()) return it->second;
      bool r = e->op == Op::Div || e->op == Op::Pow || e->op == Op::Call;
      for (const Expr& a : e->args)
        if (!r && costly(a)) r = true;
      return costly_memo[e.get()] = r;
    };
    std::unordered_set<const Node*> scanned;
    std::function<void(const Expr&)> scan = [&](const Expr& e) {
      if (!scanned.insert(e.get()).second) return;
      bool trivial = e->args.empty() || (e->op == Op::Neg && e->args[0]->args.empty());
      if (!trivial && param_only(e) && costly(e)) {
        if (!hoisted_.count(e)) {
          hoisted_[e] = fmt::format("derived{}_", hoisted_order_.size() + 1);
          hoisted_order_.push_back(e);
        }
        return;
      }
      for (const Expr& a : e->args) scan(a);
    };
    for (const Assignment& a : s_.assignments) {
      if (a.block < 0) scan(a.value);
    }
    for (const LinearBlock& lb : s_.linear_blocks) {
      for (const Expr& e : lb.a) scan(e);
      for (const Expr& e : lb.b) scan(e);
    }
    for (const Expr& e : s_.state_derivative) scan(e);
    for (const Expr& e : s_.jacobian) scan(e);
    for (const Residual& r : s_.residuals) scan(r.value);
    for (const Output& o : g_.outputs) scan(o.value);
  }

  void private_part(CppClass& c) {
    if (!scratch_.empty()) {
      c.private_members.push_back(CppStmt::comment("values one part of a long method passes to a later part"));
      for (const std::string& m : scratch_) c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;", m)));
    }
    if (!hoisted_order_.empty()) {
      c.private_members.push_back(CppStmt::comment("derived constants (set in initial())"));
      for (const Expr& e : hoisted_order_)
        c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;  // = {}", hoisted_.at(e), to_string(e, names_for_dump()))));
    }
    if (!g_.params.empty()) {
      c.private_methods.push_back({"", "double param(std::size_t i, double model_value) const",
                                   {CppStmt::line("return overridden_[i] ? overrides_[i] : model_value;")}});
      c.private_members.push_back(CppStmt::comment("parameters (set in initial())"));
      for (std::size_t i = 0; i < g_.params.size(); ++i)
        c.private_members.push_back(CppStmt::line(fmt::format("double {} = 0.0;  // {}", names_.param(static_cast<int>(i)), where(g_.params[i].loc))));
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
  int cse_counter_ = 0;
  std::map<std::string, Cost> costs_;  // method signature -> its cost
  Cost* cost_ = nullptr;               // the method being built
  std::unordered_map<Expr, std::string, ExprHash, ExprEqual> hoisted_;  // parameter expression -> member
  std::vector<Expr> hoisted_order_;                                    // in first-use order
  std::vector<std::string> scratch_;  // members of split methods (codegen/split.hpp), in order of definition
  /// Statements per part of a long method: g++ -O2 compiles the 100-rod
  /// chain's derivative (8,300 statements) in 20 s as one function.
  static constexpr std::size_t kMaxMethodLines = 2000;
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
