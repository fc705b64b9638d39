#include "elaborate/unroll.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "ir/constant.hpp"

namespace mbgc::elaborate {
namespace {

using namespace mbgc::ir;

// limits_.loop_iterations: a typo like 1..1e9 must not hang the compiler;
// limits_.unrolled_work: iterations and statements of all loops together (nested loops)
constexpr double kMaxIndex = 1e9;        // largest loop bound or name index

class Unroller {
 public:
  Unroller(const std::map<std::string, double>& overrides, const Limits& limits, Diagnostics& diags)
      : overrides_(overrides), limits_(limits), diags_(diags) {}

  AstProgram run(const AstProgram& p) {
    for (const AstStmt& s : p.stmts)
      if (auto* par = std::get_if<AstParam>(&s)) params_[par->name] = par;
    for (const auto& [name, value] : overrides_) {
      if (params_.count(name)) continue;
      std::vector<std::string> names;
      for (const auto& [n, decl] : params_) names.push_back(n);
      std::string near = closest_name(name, names);
      diags_.error(SourceLoc{}, fmt::format("--set {}: the model has no top-level parameter `{}`", name, name),
                   near.empty() ? "compile-time overrides apply to `param` declarations at the top level of the model"
                                : fmt::format("did you mean --set {}=...?", near));
    }
    AstProgram out;
    std::map<std::string, long> env;
    expand(p.stmts, env, out.stmts);
    return out;
  }

 private:
  /// Reports once: a statement inside a loop is instantiated once per iteration.
  Diagnostic* error(const SourceLoc& loc, const std::string& message, const std::string& hint) {
    if (!reported_.insert({loc.file, loc.line, loc.col, message}).second) return nullptr;
    last_ = &diags_.error(loc, message, hint);
    return last_;
  }

  /// `--set NAME=VALUE` is in the unit NAME is declared in (`{deg}`): in SI.
  double override_in_si(const std::string& name, double value) const {
    auto p = params_.find(name);
    if (p == params_.end()) return value;
    std::optional<ir::AstUnit> unit = ir::declared_unit(p->second->unit, p->second->value);
    return unit ? value * unit->unit.scale : value;
  }

  // ---- compile-time evaluation ---------------------------------------------------
  bool is_parameter(const std::string& name) const { return overrides_.count(name) || params_.count(name); }

  /// Value of a top-level parameter (is_parameter(name)); errors are reported
  /// once, where the parameter is defined, with a note at `use`.
  std::optional<double> param_value(const std::string& name, const SourceLoc& use) {
    if (auto o = overrides_.find(name); o != overrides_.end()) return override_in_si(name, o->second);
    if (auto c = cache_.find(name); c != cache_.end()) return c->second;
    const AstParam& decl = *params_.at(name);
    if (auto open = std::find(evaluating_.begin(), evaluating_.end(), name); open != evaluating_.end()) {
      std::string path;
      for (auto it = open; it != evaluating_.end(); ++it) path += *it + " -> ";
      error(decl.loc, fmt::format("parameter `{}` depends on itself ({}{})", name, path, name),
            "a loop bound or a name index needs a number: give one of these parameters a value that does not "
            "refer back to it, e.g. param N = 8");
      return std::nullopt;
    }
    evaluating_.push_back(name);
    last_ = nullptr;
    std::map<std::string, long> none;
    auto v = eval(*decl.value, none);
    evaluating_.pop_back();
    // last_ is the most recent diagnostic, so still valid
    if (!v && last_ && evaluating_.empty() && use.valid())
      last_->notes.push_back(
          {use, fmt::format("`{}` is needed at compile time here (loop bounds and name indices are unrolled by mbgc)", name)});
    cache_[name] = v;
    return v;
  }

  /// Value of an expression made of numbers, loop variables and parameters
  /// (ir::constant_value), each failure reported where it is.
  std::optional<double> eval(const AstExpr& e, const std::map<std::string, long>& env) {
    ir::ConstantRules rules;
    rules.name = [&](const AstExpr& name, int) { return name_value(name, env); };
    rules.failed = [&](const AstExpr& at, ir::NotConstant why) {
      if (why == ir::NotConstant::division_by_zero)
        error(at.loc, "division by zero in a value needed at compile time",
              "a bound or index divided by zero has no value: check the parameters in the divisor");
      else
        error(at.loc, "this expression cannot be evaluated at compile time",
              "loop bounds and name indices may use numbers, loop variables, top-level parameters and + - * / ^ "
              "(no function calls, lists or indexing)");
    };
    return ir::constant_value(e, rules);
  }

  /// A loop variable's or a top-level parameter's value; anything else is an error.
  std::optional<double> name_value(const AstExpr& e, const std::map<std::string, long>& env) {
    if (auto it = env.find(e.name); it != env.end()) return static_cast<double>(it->second);
    if (component_params_.count(e.name)) {
      error(e.loc, fmt::format("a loop inside component `{}` cannot use its parameter `{}` here", component_, e.name),
            "the loop is unrolled once, when the component is compiled, not per instance: use numbers or "
            "top-level parameters in loop bounds and name indices");
      return std::nullopt;
    }
    if (is_parameter(e.name)) return param_value(e.name, e.loc);
    std::vector<std::string> names;
    for (const auto& [n, decl] : params_) names.push_back(n);
    for (const auto& [n, v] : env) names.push_back(n);
    std::string near = closest_name(e.name, names);
    error(e.loc, fmt::format("`{}` is not known at compile time", e.name),
          near.empty() ? "loop bounds and name indices may use numbers, loop variables and top-level parameters"
                       : fmt::format("did you mean `{}`? (loop bounds and name indices may use numbers, loop "
                                     "variables and top-level parameters)",
                                     near));
    return std::nullopt;
  }

  std::optional<long> eval_integer(const AstExpr& e, const std::map<std::string, long>& env, const char* what) {
    auto v = eval(e, env);
    if (!v) return std::nullopt;
    if (!std::isfinite(*v) || std::fabs(*v) > kMaxIndex) {
      error(e.loc, fmt::format("{} is {}, beyond what mbgc can unroll", what, *v),
            fmt::format("loop bounds are integers between -{:.0f} and {:.0f}", kMaxIndex, kMaxIndex));
      return std::nullopt;
    }
    if (std::nearbyint(*v) != *v) {
      std::string from_set;
      if (e.kind == AstExpr::Kind::Name && !env.count(e.name) && overrides_.count(e.name))
        from_set = fmt::format(" (from --set {}={})", e.name, *v);
      error(e.loc, fmt::format("{} must be an integer, but it is {}{}", what, *v, from_set),
            "a loop counts whole steps: write integer bounds, e.g. for i in 1..N with param N = 8");
      return std::nullopt;
    }
    return static_cast<long>(*v);
  }

  /// A tiny parser for the text of one interpolation: integers, names, + - * / ( ).
  /// Every intermediate value stays within kMaxIndex, so nothing overflows.
  std::optional<long> eval_text(const std::string& text, const SourceLoc& loc, const std::map<std::string, long>& env) {
    std::size_t pos = 0;
    bool ok = true;
    const std::string usual = "write an integer expression of loop variables and parameters, e.g. link{i-1}";
    auto fail = [&](const std::string& why, const std::string& hint = {}) {
      if (ok) error(loc, fmt::format("cannot evaluate `{{{}}}` in a name: {}", text, why), hint.empty() ? usual : hint);
      ok = false;
      return 0L;
    };
    auto bounded = [&](long v) {
      if (ok && std::labs(v) > static_cast<long>(kMaxIndex))
        return fail(fmt::format("the index exceeds {:.0f}", kMaxIndex), "name indices count things: keep them small");
      return v;
    };
    std::function<long()> sum;
    std::function<long()> atom = [&]() -> long {
      if (!ok) return 0;
      if (pos >= text.size()) return fail("it ends too early");
      char c = text[pos];
      if (c == '-') { ++pos; return -atom(); }
      if (c == '(') {
        ++pos;
        long v = sum();
        if (pos >= text.size() || text[pos] != ')') return fail("a `)` is missing");
        ++pos;
        return v;
      }
      if (std::isdigit(static_cast<unsigned char>(c))) {
        std::size_t start = pos;
        long v = 0;
        while (pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos]))) {
          v = bounded(v * 10 + (text[pos++] - '0'));
          if (!ok) return 0;
        }
        if (pos < text.size() && (text[pos] == '.' || text[pos] == 'e' || text[pos] == 'E')) {
          std::size_t end = pos + 1;
          while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '.')) ++end;
          return fail(fmt::format("`{}` is not an integer", text.substr(start, end - start)),
                      "a name index is an integer, e.g. link{i+1}");
        }
        return v;
      }
      if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        std::string name;
        while (pos < text.size() && (std::isalnum(static_cast<unsigned char>(text[pos])) || text[pos] == '_')) name += text[pos++];
        if (auto it = env.find(name); it != env.end()) return it->second;
        if (component_params_.count(name))
          return fail(fmt::format("`{}` is a parameter of component `{}`, not known when the loop is unrolled", name, component_),
                      "use numbers, loop variables or top-level parameters in name indices");
        if (!is_parameter(name)) {
          std::vector<std::string> names;
          for (const auto& [n, v] : env) names.push_back(n);
          for (const auto& [n, decl] : params_) names.push_back(n);
          std::string near = closest_name(name, names);
          return fail(fmt::format("`{}` is not a loop variable or a top-level parameter", name),
                      near.empty() ? usual : fmt::format("did you mean `{}`?", near));
        }
        auto v = param_value(name, loc);
        if (!v) { ok = false; return 0; }  // reported where the parameter is defined
        if (std::nearbyint(*v) != *v || std::fabs(*v) > kMaxIndex)
          return fail(fmt::format("`{}` is {}, not an integer", name, *v), "name indices need integer parameters");
        return static_cast<long>(*v);
      }
      return fail(fmt::format("unexpected `{}`", c), "a name index may use + - * / and ( ), e.g. n{i}_{2*j+1}");
    };
    std::function<long()> product = [&]() -> long {
      long v = atom();
      while (ok && pos < text.size() && (text[pos] == '*' || text[pos] == '/')) {
        char op = text[pos++];
        long w = atom();
        if (!ok) return 0;
        if (op == '/' && w == 0) {
          std::string values;
          for (const auto& [n, x] : env) values += fmt::format("{}{} = {}", values.empty() ? "" : ", ", n, x);
          return fail(fmt::format("division by zero{}", values.empty() ? "" : " (for " + values + ")"),
                      "the divisor must not vanish for any value of the loop variables");
        }
        v = bounded(op == '*' ? v * w : v / w);
      }
      return v;
    };
    sum = [&]() -> long {
      long v = product();
      while (ok && pos < text.size() && (text[pos] == '+' || text[pos] == '-')) {
        char op = text[pos++];
        long w = product();
        if (!ok) return 0;
        v = bounded(op == '+' ? v + w : v - w);
      }
      return v;
    };
    long v = sum();
    if (ok && pos != text.size())
      fail(fmt::format("unexpected `{}`", text[pos]), "a name index may use + - * / and ( ), e.g. n{i}_{2*j+1}");
    if (!ok) return std::nullopt;
    return v;
  }

  /// "link{i-1}.tip" -> "link2.tip" (for i = 3).
  std::string interpolate(const std::string& name, const SourceLoc& loc, const std::map<std::string, long>& env) {
    if (name.find('{') == std::string::npos) return name;
    std::string out;
    for (std::size_t i = 0; i < name.size(); ++i) {
      if (name[i] != '{') {
        out += name[i];
        continue;
      }
      std::size_t depth = 1, j = i + 1;
      while (j < name.size() && depth) {
        if (name[j] == '{') ++depth;
        if (name[j] == '}') --depth;
        ++j;
      }
      std::string inner = name.substr(i + 1, j - i - 2);
      if (auto v = eval_text(inner, loc, env)) out += std::to_string(*v);
      i = j - 1;
    }
    return out;
  }

  // ---- substitution ------------------------------------------------------------------
  AstExprPtr subst(const AstExprPtr& e, const std::map<std::string, long>& env) {
    if (!e || env.empty()) return e;
    auto copy = std::make_shared<AstExpr>(*e);
    if (e->kind == AstExpr::Kind::Name) {
      if (auto it = env.find(e->name); it != env.end()) {
        copy->kind = AstExpr::Kind::Number;
        copy->number = static_cast<double>(it->second);
        copy->name.clear();
        return copy;
      }
      copy->name = interpolate(e->name, e->loc, env);
      return copy;
    }
    for (AstExprPtr& a : copy->args) a = subst(a, env);
    return copy;
  }
  void subst_attrs(std::vector<AstAttr>& attrs, const std::map<std::string, long>& env) {
    for (AstAttr& a : attrs) a.value = subst(a.value, env);
  }
  void subst_end(AstEndpoint& p, const std::map<std::string, long>& env) { p.path = interpolate(p.path, p.loc, env); }

  AstStmt instantiate(const AstStmt& s, const std::map<std::string, long>& env) {
    AstStmt out = s;
    std::visit(
        [&](auto& st) {
          using T = std::decay_t<decltype(st)>;
          if constexpr (std::is_same_v<T, AstParam> || std::is_same_v<T, AstSignal> || std::is_same_v<T, AstOutput>) {
            st.name = interpolate(st.name, st.loc, env);
            st.value = subst(st.value, env);
          } else if constexpr (std::is_same_v<T, AstElement>) {
            st.name = interpolate(st.name, st.loc, env);
            st.value = subst(st.value, env);
            subst_attrs(st.attrs, env);
          } else if constexpr (std::is_same_v<T, AstJunction>) {
            st.name = interpolate(st.name, st.loc, env);
            for (AstEndpoint& p : st.inputs) subst_end(p, env);
            for (AstEndpoint& p : st.outputs) subst_end(p, env);
          } else if constexpr (std::is_same_v<T, AstBond>) {
            st.name = interpolate(st.name, st.loc, env);
            subst_end(st.from, env);
            subst_end(st.to, env);
          } else if constexpr (std::is_same_v<T, AstInstance>) {
            st.name = interpolate(st.name, st.loc, env);
            subst_attrs(st.args, env);
          } else if constexpr (std::is_same_v<T, AstBody>) {
            st.name = interpolate(st.name, st.loc, env);
            subst_attrs(st.attrs, env);
            for (AstPoint& p : st.points) p = instantiate_point(p, env);  // the loops inside: by flatten_points
          } else if constexpr (std::is_same_v<T, AstJoint>) {
            st.name = interpolate(st.name, st.loc, env);
            subst_end(st.a, env);
            subst_end(st.b, env);
            subst_attrs(st.attrs, env);
          } else if constexpr (std::is_same_v<T, AstSetting>) {
            st.value = subst(st.value, env);
          } else if constexpr (std::is_same_v<T, std::shared_ptr<AstFor>>) {
            auto copy = std::make_shared<AstFor>(*st);
            copy->from = subst(st->from, env);
            copy->to = subst(st->to, env);
            st = copy;  // the body is substituted when the inner loop is expanded (env is passed down)
          }
        },
        out);
    return out;
  }

  /// A loop's bounds, or nullopt after reporting why it cannot be unrolled:
  /// its variable hides an outer one, a bound is not a constant integer, or
  /// it would repeat more than limits_.loop_iterations times. (A loop of statements or of points.)
  template <class Loop>
  std::optional<std::pair<long, long>> loop_range(const Loop& f, const std::map<std::string, long>& env) {
    if (env.count(f.var)) {
      error(f.loc, fmt::format("loop variable `{}` hides an outer loop's variable", f.var),
            fmt::format("rename the inner loop's variable, e.g. for {}2 in ...", f.var));
      return std::nullopt;
    }
    auto from = eval_integer(*f.from, env, "a loop's lower bound");
    auto to = eval_integer(*f.to, env, "a loop's upper bound");
    if (!from || !to) return std::nullopt;
    if (*to - *from >= limits_.loop_iterations) {
      error(f.loc, fmt::format("this loop would repeat its body {} times", *to - *from + 1),
            fmt::format("mbgc writes out every repetition at compile time: at most {} per loop", limits_.loop_iterations));
      return std::nullopt;
    }
    return std::pair{*from, *to};
  }

  AstPoint instantiate_point(const AstPoint& p, const std::map<std::string, long>& env) {
    return {interpolate(p.name, p.loc, env), p.loc, subst(p.value, env)};
  }

  /// The points of a body or ground block with its `for` loops unrolled, each
  /// loop's points where the loop stands. `env` is already substituted into `points`.
  std::vector<AstPoint> flatten_points(const std::vector<AstPoint>& points,
                                       const std::vector<std::shared_ptr<AstPointFor>>& loops,
                                       const std::map<std::string, long>& env, const SourceLoc* outermost) {
    std::vector<AstPoint> out;
    std::size_t next_loop = 0;
    for (std::size_t k = 0; k <= points.size(); ++k) {
      for (; next_loop < loops.size() && loops[next_loop]->position == k; ++next_loop) {
        const AstPointFor& f = *loops[next_loop];
        const auto range = loop_range(f, env);
        if (!range) continue;
        const auto [from, to] = *range;
        const SourceLoc& top = outermost ? *outermost : f.loc;
        for (long i = from; i <= to; ++i) {
          if (++work_ > limits_.unrolled_work) {
            give_up(top);
            return out;
          }
          std::map<std::string, long> inner = env;
          inner[f.var] = i;
          std::vector<AstPoint> body;
          for (const AstPoint& p : f.points) {
            body.push_back(instantiate_point(p, inner));
            point_loop_var_[{p.loc.file, p.loc.line, p.loc.col}] = f.var;
          }
          work_ += static_cast<long>(body.size());
          for (AstPoint& p : flatten_points(body, f.loops, inner, &top)) out.push_back(std::move(p));
          if (gave_up_) return out;
        }
      }
      if (k < points.size()) out.push_back(points[k]);
    }
    return out;
  }

  /// A body or ground block: its loops unrolled; a point that one statement
  /// declares again with the same name (a loop's name without the loop
  /// variable) is reported here, where the loop can be named.
  AstBody flatten_body(const AstBody& b, const std::map<std::string, long>& env, const AstFor* outermost) {
    AstBody out = b;
    out.loops.clear();
    out.points = flatten_points(b.points, b.loops, env, outermost ? &outermost->loc : nullptr);
    std::map<std::string, const AstPoint*> seen;
    for (const AstPoint& p : out.points) {
      const AstPoint* first = seen.emplace(p.name, &p).first->second;
      if (first != &p && same_place(first->loc, p.loc)) repeated_point(p, out.name);
    }
    if (out.name == "ground") {  // ground blocks add up: a loop may repeat the whole block
      for (const AstPoint& p : out.points) {
        auto [it, fresh] = ground_points_.emplace(p.name, p.loc);
        if (!fresh && same_place(it->second, p.loc)) repeated_point(p, "ground");
      }
    }
    return out;
  }
  static bool same_place(const SourceLoc& a, const SourceLoc& b) {
    return a.file == b.file && a.line == b.line && a.col == b.col;
  }
  void repeated_point(const AstPoint& p, const std::string& owner) {
    auto var = point_loop_var_.find({p.loc.file, p.loc.line, p.loc.col});
    error(p.loc, fmt::format("point `{}` of `{}` is declared again in every iteration of the loop", p.name, owner),
          fmt::format("interpolate the loop variable into the name, e.g. {}{{{}}}", p.name,
                      var != point_loop_var_.end() ? var->second : loop_var_));
  }

  void expand(const std::vector<AstStmt>& stmts, const std::map<std::string, long>& env, std::vector<AstStmt>& out,
              const AstFor* outermost = nullptr) {
    for (const AstStmt& s : stmts) {
      if (gave_up_) return;
      if (auto* loop = std::get_if<std::shared_ptr<AstFor>>(&s)) {
        const AstFor& f = **loop;
        const auto range = loop_range(f, env);
        if (!range) continue;
        const auto [from, to] = *range;
        const AstFor* top = outermost ? outermost : &f;
        for (long i = from; i <= to; ++i) {
          if (++work_ > limits_.unrolled_work) return give_up(top->loc);
          std::map<std::string, long> inner = env;
          inner[f.var] = i;
          const std::string outer_var = std::exchange(loop_var_, f.var);
          std::vector<AstStmt> body;
          for (const AstStmt& b : f.body) body.push_back(instantiate(b, inner));
          expand(body, inner, out, top);
          loop_var_ = outer_var;
          if (gave_up_) return;
        }
        continue;
      }
      if (outermost && ++work_ > limits_.unrolled_work) return give_up(outermost->loc);
      if (auto* b = std::get_if<AstBody>(&s)) {
        out.push_back(flatten_body(*b, env, outermost));
        continue;
      }
      if (auto* comp = std::get_if<std::shared_ptr<AstComponent>>(&s)) {
        out.push_back(unroll_component(**comp));
        continue;
      }
      if (auto* par = std::get_if<AstParam>(&s); par && env.empty() && component_.empty()) {
        if (auto o = overrides_.find(par->name); o != overrides_.end()) {
          // the value given, in the unit the parameter is declared in
          AstParam copy = *par;
          copy.unit = ir::declared_unit(par->unit, par->value);
          auto num = std::make_shared<AstExpr>();
          num->kind = AstExpr::Kind::Number;
          num->loc = par->value->loc;
          num->number = copy.unit ? o->second * copy.unit->unit.scale : o->second;
          copy.value = num;
          out.push_back(copy);
          continue;
        }
      }
      out.push_back(s);
    }
  }

  void give_up(const SourceLoc& outermost) {
    if (gave_up_) return;
    gave_up_ = true;
    error(outermost, fmt::format("these nested loops unroll into more than {} statements and iterations", limits_.unrolled_work),
          "mbgc writes out every repetition at compile time: make the ranges smaller");
  }

  /// A component's loops are unrolled once, in its declaration: their bounds
  /// may use top-level parameters, not the component's own.
  std::shared_ptr<AstComponent> unroll_component(const AstComponent& c) {
    auto copy = std::make_shared<AstComponent>(c);
    component_ = c.name;
    for (const AstParam& p : c.params) component_params_.insert(p.name);
    copy->body.clear();
    std::map<std::string, long> env;
    expand(c.body, env, copy->body);
    component_.clear();
    component_params_.clear();
    return copy;
  }

  const std::map<std::string, double>& overrides_;
  const Limits& limits_;
  Diagnostics& diags_;
  std::map<std::string, const AstParam*> params_;
  std::map<std::string, std::optional<double>> cache_;  // parameter values (nullopt: failed, reported)
  std::vector<std::string> evaluating_;                 // parameters being evaluated (cycle detection)
  std::set<std::tuple<int, int, int, std::string>> reported_;
  Diagnostic* last_ = nullptr;                          // the most recent error
  std::string component_;                               // the component whose loops are unrolled
  std::set<std::string> component_params_;
  std::map<std::string, SourceLoc> ground_points_;      // every ground point so far, where declared
  std::map<std::tuple<int, int, int>, std::string> point_loop_var_;  // a body loop's points: the loop's variable
  std::string loop_var_ = "i";                          // the innermost statement loop's variable
  long work_ = 0;
  bool gave_up_ = false;
};

}  // namespace

AstProgram unroll_loops(const AstProgram& program, const std::map<std::string, double>& overrides, Diagnostics& diags,
                        const Limits& limits) {
  Unroller u(overrides, limits, diags);
  return u.run(program);
}

}  // namespace mbgc::elaborate
