#include "ir/value.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>

namespace mbgc::ir {

std::string Value::shape() const {
  if (is_scalar()) return "a scalar";
  if (cols == 1) return fmt::format("a {}-vector", rows);
  return fmt::format("a {}x{} matrix", rows, cols);
}

namespace {

struct FnInfo {
  int min_args;
  int max_args;
};

// Functions of the language. The time-source helpers (step, ramp, sine) take
// explicit parameters and read the time t implicitly.
const std::map<std::string, FnInfo> kFunctions = {
    {"sin", {1, 1}},   {"cos", {1, 1}},   {"tan", {1, 1}},  {"asin", {1, 1}}, {"acos", {1, 1}},
    {"atan", {1, 1}},  {"atan2", {2, 2}}, {"sinh", {1, 1}}, {"cosh", {1, 1}}, {"tanh", {1, 1}},
    {"exp", {1, 1}},   {"log", {1, 1}},   {"sqrt", {1, 1}}, {"abs", {1, 1}},  {"sign", {1, 1}},
    {"min", {2, 2}},   {"max", {2, 2}},   {"step", {1, 2}}, {"ramp", {1, 2}}, {"sine", {2, 3}},
    {"diag", {1, 1000}}, {"heaviside", {1, 1}},
};

const std::map<std::string, Fn> kScalarFns = {
    {"sin", Fn::Sin},   {"cos", Fn::Cos},   {"tan", Fn::Tan},     {"asin", Fn::Asin},
    {"acos", Fn::Acos}, {"atan", Fn::Atan}, {"atan2", Fn::Atan2}, {"sinh", Fn::Sinh},
    {"cosh", Fn::Cosh}, {"tanh", Fn::Tanh}, {"exp", Fn::Exp},     {"log", Fn::Log},
    {"sqrt", Fn::Sqrt}, {"abs", Fn::Abs},   {"sign", Fn::Sign},   {"min", Fn::Min},
    {"max", Fn::Max},     {"heaviside", Fn::Step},
};

class Lowerer {
 public:
  Lowerer(const NameLookup& lookup, Diagnostics& diags) : lookup_(lookup), diags_(diags) {}

  std::optional<Value> run(const AstExpr& e) {
    switch (e.kind) {
      case AstExpr::Kind::Number: return Value::scalar(constant(e.number));
      case AstExpr::Kind::Name: return name(e);
      case AstExpr::Kind::Unary: {
        auto a = run(*e.args[0]);
        if (!a) return a;
        if (e.op == '-')
          for (Expr& x : a->items) x = neg(x);
        return a;
      }
      case AstExpr::Kind::Binary: return binary(e);
      case AstExpr::Kind::Call: return call_fn(e);
      case AstExpr::Kind::Index: return index(e);
      case AstExpr::Kind::List: return list(e);
    }
    return std::nullopt;
  }

 private:
  std::optional<Value> name(const AstExpr& e) {
    if (e.name == "t") return Value::scalar(time());
    if (e.name == "pi") return Value::scalar(constant(M_PI));
    return lookup_(e.name, e.loc);
  }

  std::optional<Value> binary(const AstExpr& e) {
    auto a = run(*e.args[0]);
    auto b = run(*e.args[1]);
    if (!a || !b) return std::nullopt;
    auto elementwise = [&](auto op) -> std::optional<Value> {
      if (a->is_scalar() && !b->is_scalar()) {
        Value r = *b;
        for (Expr& x : r.items) x = op(a->items[0], x);
        return r;
      }
      if (b->is_scalar()) {
        Value r = *a;
        for (Expr& x : r.items) x = op(x, b->items[0]);
        return r;
      }
      if (a->rows != b->rows || a->cols != b->cols) {
        diags_.error(e.loc, fmt::format("cannot apply `{}` to {} and {}", e.op, a->shape(), b->shape()),
                     "both sides must have the same shape, or one must be a scalar");
        return std::nullopt;
      }
      Value r = *a;
      for (std::size_t i = 0; i < r.items.size(); ++i) r.items[i] = op(a->items[i], b->items[i]);
      return r;
    };
    switch (e.op) {
      case '+': return elementwise([](const Expr& x, const Expr& y) { return add(x, y); });
      case '-': return elementwise([](const Expr& x, const Expr& y) { return sub(x, y); });
      case '*':
        if (a->is_scalar() || b->is_scalar())
          return elementwise([](const Expr& x, const Expr& y) { return mul(x, y); });
        return matmul(e, *a, *b);
      case '/':
        if (!b->is_scalar()) {
          diags_.error(e.loc, fmt::format("cannot divide by {}", b->shape()), "divide by a scalar only");
          return std::nullopt;
        }
        return elementwise([](const Expr& x, const Expr& y) { return div(x, y); });
      case '^':
        if (!a->is_scalar() || !b->is_scalar()) {
          diags_.error(e.loc, "`^` needs scalar operands", "raise scalars to scalar powers");
          return std::nullopt;
        }
        return Value::scalar(pow(a->items[0], b->items[0]));
    }
    return std::nullopt;
  }

  std::optional<Value> matmul(const AstExpr& e, const Value& a, const Value& b) {
    if (a.cols != b.rows) {
      diags_.error(e.loc, fmt::format("matrix product of {} and {}: inner dimensions differ", a.shape(), b.shape()),
                   "an (n x m) matrix multiplies an (m x k) one");
      return std::nullopt;
    }
    Value r{a.rows, b.cols, {}};
    for (int i = 0; i < a.rows; ++i)
      for (int j = 0; j < b.cols; ++j) {
        Expr s = constant(0);
        for (int k = 0; k < a.cols; ++k) s = add(s, mul(a.at(i, k), b.at(k, j)));
        r.items.push_back(s);
      }
    return r;
  }

  std::optional<Value> call_fn(const AstExpr& e) {
    auto it = kFunctions.find(e.name);
    if (it == kFunctions.end()) {
      std::string near = closest_name(e.name, function_names());
      diags_.error(e.loc, fmt::format("unknown function `{}`", e.name),
                   near.empty() ? "functions: sin cos tan atan2 exp log sqrt abs min max step ramp sine diag ..."
                                : fmt::format("did you mean `{}`?", near));
      return std::nullopt;
    }
    int n = static_cast<int>(e.args.size());
    if (n < it->second.min_args || n > it->second.max_args) {
      std::string expected = it->second.min_args == it->second.max_args
                                 ? fmt::format("{}", it->second.min_args)
                                 : fmt::format("{} to {}", it->second.min_args, it->second.max_args);
      diags_.error(e.loc, fmt::format("`{}` takes {} argument{}, but {} {} given", e.name, expected,
                                      it->second.max_args == 1 ? "" : "s", n, n == 1 ? "was" : "were"),
                   call_hint(e.name));
      return std::nullopt;
    }
    std::vector<Expr> args;
    for (const auto& a : e.args) {
      auto v = run(*a);
      if (!v) return std::nullopt;
      if (!v->is_scalar()) {
        diags_.error(a->loc, fmt::format("`{}` expects scalar arguments, this is {}", e.name, v->shape()),
                     "index the vector, e.g. v[1]");
        return std::nullopt;
      }
      args.push_back(v->items[0]);
    }
    if (e.name == "diag") {
      Value r{n, n, {}};
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) r.items.push_back(i == j ? args[static_cast<std::size_t>(i)] : constant(0));
      return r;
    }
    if (e.name == "step") {  // step(t0[, height]) = height for t >= t0
      Expr h = n > 1 ? args[1] : constant(1);
      return Value::scalar(mul(h, call(Fn::Step, {sub(time(), args[0])})));
    }
    if (e.name == "ramp") {  // ramp(t0[, slope]) = slope * max(0, t - t0)
      Expr s = n > 1 ? args[1] : constant(1);
      return Value::scalar(mul(s, call(Fn::Max, {constant(0), sub(time(), args[0])})));
    }
    if (e.name == "sine") {  // sine(amplitude, f_hz[, phase_rad])
      Expr phase = n > 2 ? args[2] : constant(0);
      return Value::scalar(
          mul(args[0], call(Fn::Sin, {add(mul(mul(constant(2 * M_PI), args[1]), time()), phase)})));
    }
    return Value::scalar(call(kScalarFns.at(e.name), std::move(args)));
  }

  static std::string call_hint(const std::string& fn) {
    if (fn == "step") return "write step(t0) or step(t0, height)";
    if (fn == "ramp") return "write ramp(t0) or ramp(t0, slope)";
    if (fn == "sine") return "write sine(amplitude, frequency_hz) or sine(amplitude, frequency_hz, phase_rad)";
    if (fn == "atan2") return "write atan2(y, x)";
    if (fn == "min" || fn == "max") return fmt::format("write {}(a, b)", fn);
    return fmt::format("write {}(x)", fn);
  }

  std::optional<Value> index(const AstExpr& e) {
    auto base = run(*e.args[0]);
    if (!base) return base;
    std::vector<int> idx;
    for (std::size_t k = 1; k < e.args.size(); ++k) {
      auto v = run(*e.args[k]);
      if (!v) return std::nullopt;
      double c = 0;
      if (!v->is_scalar() || !is_const(v->items[0], &c) || c != std::floor(c)) {
        diags_.error(e.args[k]->loc, "an index must be a constant integer", "indices are 1-based: v[1], M[2, 3]");
        return std::nullopt;
      }
      idx.push_back(static_cast<int>(c));
    }
    int r = 0, c = 0;
    if (idx.size() == 1) {
      if (!base->is_vector()) {
        diags_.error(e.loc, fmt::format("{} needs two indices", base->shape()), "write M[row, column]");
        return std::nullopt;
      }
      int i = idx[0];
      if (i < 1 || i > base->length()) {
        diags_.error(e.args[1]->loc, fmt::format("index {} is out of range for {}", i, base->shape()),
                     fmt::format("valid indices are 1 to {}", base->length()));
        return std::nullopt;
      }
      return Value::scalar(base->items[static_cast<std::size_t>(i - 1)]);
    }
    r = idx[0];
    c = idx[1];
    if (r < 1 || r > base->rows || c < 1 || c > base->cols) {
      diags_.error(e.loc, fmt::format("index [{}, {}] is out of range for {}", r, c, base->shape()),
                   fmt::format("rows are 1 to {}, columns 1 to {}", base->rows, base->cols));
      return std::nullopt;
    }
    return Value::scalar(base->at(r - 1, c - 1));
  }

  std::optional<Value> list(const AstExpr& e) {
    if (e.args.empty()) {
      diags_.error(e.loc, "empty list", "write a vector as [a, b, c]");
      return std::nullopt;
    }
    std::vector<Value> rows;
    for (const auto& a : e.args) {
      auto v = run(*a);
      if (!v) return std::nullopt;
      rows.push_back(std::move(*v));
    }
    if (rows[0].is_scalar()) {  // a column vector
      Value r{static_cast<int>(rows.size()), 1, {}};
      for (std::size_t i = 0; i < rows.size(); ++i) {
        if (!rows[i].is_scalar()) {
          diags_.error(e.args[i]->loc, "mixed scalars and lists in a vector", "write [a, b] or [[a, b], [c, d]]");
          return std::nullopt;
        }
        r.items.push_back(rows[i].items[0]);
      }
      return r;
    }
    int cols = rows[0].length();
    Value r{static_cast<int>(rows.size()), cols, {}};
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (!rows[i].is_vector() || rows[i].length() != cols || rows[i].is_scalar()) {
        diags_.error(e.args[i]->loc, fmt::format("row {} has {} entries, row 1 has {}", i + 1, rows[i].length(), cols),
                     "every row of a matrix needs the same number of entries");
        return std::nullopt;
      }
      for (const Expr& x : rows[i].items) r.items.push_back(x);
    }
    return r;
  }

  const NameLookup& lookup_;
  Diagnostics& diags_;
};

}  // namespace

std::optional<Value> lower(const AstExpr& e, const NameLookup& lookup, Diagnostics& diags) {
  Lowerer l(lookup, diags);
  return l.run(e);
}

std::vector<std::string> function_names() {
  std::vector<std::string> names;
  for (const auto& [n, info] : kFunctions) names.push_back(n);
  return names;
}

}  // namespace mbgc::ir
