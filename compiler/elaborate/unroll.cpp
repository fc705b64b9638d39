#include "elaborate/unroll.hpp"

#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <optional>
#include <set>

namespace mbgc::elaborate {
namespace {

using namespace mbgc::ir;

constexpr long kMaxIterations = 100000;  // a typo like 1..1e9 must not hang the compiler

class Unroller {
 public:
  Unroller(const std::map<std::string, double>& overrides, Diagnostics& diags) : overrides_(overrides), diags_(diags) {}

  AstProgram run(const AstProgram& p) {
    for (const AstStmt& s : p.stmts)
      if (auto* par = std::get_if<AstParam>(&s)) params_[par->name] = par;
    for (const auto& [name, value] : overrides_) {
      if (!params_.count(name))
        diags_.error(SourceLoc{}, fmt::format("--set {}: the model has no top-level parameter `{}`", name, name),
                     "compile-time overrides apply to `param` declarations at the top level of the model");
    }
    AstProgram out;
    std::map<std::string, long> env;
    expand(p.stmts, env, out.stmts);
    return out;
  }

 private:
  // ---- compile-time evaluation ---------------------------------------------------
  std::optional<double> param_value(const std::string& name, const SourceLoc& loc) {
    if (auto o = overrides_.find(name); o != overrides_.end()) return o->second;
    auto it = params_.find(name);
    if (it == params_.end()) return std::nullopt;
    if (evaluating_.count(name)) {
      diags_.error(loc, fmt::format("parameter `{}` depends on itself", name), "");
      return std::nullopt;
    }
    evaluating_.insert(name);
    std::map<std::string, long> none;
    auto v = eval(*it->second->value, none);
    evaluating_.erase(name);
    return v;
  }

  /// Value of an expression made of numbers, loop variables and parameters.
  std::optional<double> eval(const AstExpr& e, const std::map<std::string, long>& env) {
    switch (e.kind) {
      case AstExpr::Kind::Number: return e.number;
      case AstExpr::Kind::Name: {
        if (auto it = env.find(e.name); it != env.end()) return static_cast<double>(it->second);
        if (auto v = param_value(e.name, e.loc)) return v;
        diags_.error(e.loc, fmt::format("`{}` is not known at compile time", e.name),
                     "loop bounds and name interpolations may use numbers, loop variables and top-level parameters");
        return std::nullopt;
      }
      case AstExpr::Kind::Unary: {
        auto a = eval(*e.args[0], env);
        if (!a) return a;
        return e.op == '-' ? -*a : *a;
      }
      case AstExpr::Kind::Binary: {
        auto a = eval(*e.args[0], env);
        auto b = eval(*e.args[1], env);
        if (!a || !b) return std::nullopt;
        switch (e.op) {
          case '+': return *a + *b;
          case '-': return *a - *b;
          case '*': return *a * *b;
          case '/': return *a / *b;
          case '^': return std::pow(*a, *b);
        }
        return std::nullopt;
      }
      default:
        diags_.error(e.loc, "this expression cannot be evaluated at compile time",
                     "loop bounds may use + - * / ^, numbers, loop variables and top-level parameters");
        return std::nullopt;
    }
  }

  std::optional<long> eval_integer(const AstExpr& e, const std::map<std::string, long>& env, const char* what) {
    auto v = eval(e, env);
    if (!v) return std::nullopt;
    if (!std::isfinite(*v) || std::nearbyint(*v) != *v || std::fabs(*v) > 1e9) {
      diags_.error(e.loc, fmt::format("{} must be an integer, but it is {}", what, *v), "");
      return std::nullopt;
    }
    return static_cast<long>(*v);
  }

  /// A tiny parser for the text of one interpolation: integers, names, + - * / ( ).
  std::optional<long> eval_text(const std::string& text, const SourceLoc& loc, const std::map<std::string, long>& env) {
    std::size_t pos = 0;
    bool ok = true;
    auto fail = [&](const std::string& why) {
      if (ok) diags_.error(loc, fmt::format("cannot evaluate `{{{}}}` in a name: {}", text, why),
                           "write an integer expression of loop variables and parameters, e.g. link{i-1}");
      ok = false;
      return 0L;
    };
    std::function<long()> sum;
    std::function<long()> atom = [&]() -> long {
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
        long v = 0;
        while (pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos]))) v = v * 10 + (text[pos++] - '0');
        return v;
      }
      if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        std::string name;
        while (pos < text.size() && (std::isalnum(static_cast<unsigned char>(text[pos])) || text[pos] == '_')) name += text[pos++];
        if (auto it = env.find(name); it != env.end()) return it->second;
        auto v = param_value(name, loc);
        if (!v || std::nearbyint(*v) != *v) return fail(fmt::format("`{}` is not an integer known at compile time", name));
        return static_cast<long>(*v);
      }
      return fail(fmt::format("unexpected `{}`", c));
    };
    std::function<long()> product = [&]() -> long {
      long v = atom();
      while (ok && pos < text.size() && (text[pos] == '*' || text[pos] == '/')) {
        char op = text[pos++];
        long w = atom();
        if (op == '/' && w == 0) return fail("division by zero");
        v = op == '*' ? v * w : v / w;
      }
      return v;
    };
    sum = [&]() -> long {
      long v = product();
      while (ok && pos < text.size() && (text[pos] == '+' || text[pos] == '-')) {
        char op = text[pos++];
        long w = product();
        v = op == '+' ? v + w : v - w;
      }
      return v;
    };
    long v = sum();
    if (ok && pos != text.size()) fail(fmt::format("unexpected `{}`", text[pos]));
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
            for (AstPoint& p : st.points) p.value = subst(p.value, env);
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

  void expand(const std::vector<AstStmt>& stmts, const std::map<std::string, long>& env, std::vector<AstStmt>& out) {
    for (const AstStmt& s : stmts) {
      if (auto* loop = std::get_if<std::shared_ptr<AstFor>>(&s)) {
        const AstFor& f = **loop;
        if (env.count(f.var)) {
          diags_.error(f.loc, fmt::format("loop variable `{}` hides an outer loop's variable", f.var), "use another name");
          continue;
        }
        auto from = eval_integer(*f.from, env, "a loop's lower bound");
        auto to = eval_integer(*f.to, env, "a loop's upper bound");
        if (!from || !to) continue;
        if (*to - *from >= kMaxIterations) {
          diags_.error(f.loc, fmt::format("this loop would repeat its body {} times", *to - *from + 1),
                       fmt::format("mbgc unrolls loops; at most {} iterations", kMaxIterations));
          continue;
        }
        for (long i = *from; i <= *to; ++i) {
          std::map<std::string, long> inner = env;
          inner[f.var] = i;
          std::vector<AstStmt> body;
          for (const AstStmt& b : f.body) body.push_back(instantiate(b, inner));
          expand(body, inner, out);
        }
        continue;
      }
      if (auto* par = std::get_if<AstParam>(&s); par && env.empty()) {
        if (auto o = overrides_.find(par->name); o != overrides_.end()) {
          AstParam copy = *par;
          auto num = std::make_shared<AstExpr>();
          num->kind = AstExpr::Kind::Number;
          num->loc = par->value->loc;
          num->number = o->second;
          copy.value = num;
          out.push_back(copy);
          continue;
        }
      }
      out.push_back(s);
    }
  }

  const std::map<std::string, double>& overrides_;
  Diagnostics& diags_;
  std::map<std::string, const AstParam*> params_;
  std::set<std::string> evaluating_;
};

}  // namespace

AstProgram unroll_loops(const AstProgram& program, const std::map<std::string, double>& overrides, Diagnostics& diags) {
  Unroller u(overrides, diags);
  return u.run(program);
}

}  // namespace mbgc::elaborate
