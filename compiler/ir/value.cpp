#include "ir/value.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>
#include <utility>

#include "units/unit.hpp"

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
  bool shaped = false;  // takes vectors/matrices (else every argument must be a scalar)
};

// Functions of the language. The time-source helpers (step, ramp, sine) take
// explicit parameters and read the time t implicitly. The shaped ones build or
// transform vectors and matrices (quaternions are 4-vectors [w, x, y, z]).
const std::map<std::string, FnInfo> kFunctions = {
    {"sin", {1, 1}},   {"cos", {1, 1}},   {"tan", {1, 1}},  {"asin", {1, 1}}, {"acos", {1, 1}},
    {"atan", {1, 1}},  {"atan2", {2, 2}}, {"sinh", {1, 1}}, {"cosh", {1, 1}}, {"tanh", {1, 1}},
    {"exp", {1, 1}},   {"log", {1, 1}},   {"sqrt", {1, 1}}, {"abs", {1, 1}},  {"sign", {1, 1}},
    {"min", {2, 2}},   {"max", {2, 2}},   {"step", {1, 2}}, {"ramp", {1, 2}}, {"sine", {2, 3}},
    {"diag", {1, 1000}}, {"heaviside", {1, 1}}, {"select", {1, 1}},
    // shaped
    {"eye", {1, 1, true}},        {"zeros", {1, 2, true}},     {"transpose", {1, 1, true}},
    {"dot", {2, 2, true}},        {"cross", {2, 2, true}},     {"skew", {1, 1, true}},
    {"norm", {1, 1, true}},       {"hcat", {1, 1000, true}},   {"vcat", {1, 1000, true}},
    {"rotq", {1, 1, true}},       {"quat_rate", {1, 1, true}}, {"quat_mul", {2, 2, true}},
    {"quat_conj", {1, 1, true}},  {"quat_axis_angle", {2, 2, true}}, {"rot_axis_angle", {2, 2, true}},
    {"quat_arc", {1, 1, true}},   {"bryant", {1, 1, true}},    {"jacobian", {2, 2, true}},
    {"partial_t", {1, 1, true}},  {"frozen", {1, 1, true}},   {"table", {2, 2, true}},
};

// Most points a table() may list (a typo must not write a huge expression).
constexpr int kMaxTablePoints = 10000;

// Largest dimension eye() and zeros() build (a typo must not exhaust memory).
constexpr int kMaxDimension = 1000;

using Vec = std::vector<Expr>;

Expr sq(const Expr& a) { return mul(a, a); }
Expr twice(const Expr& a) { return mul(constant(2), a); }

/// The rotation by `angle` about `axis` (normalised here), Rodrigues' form
/// c I + s [u]x + (1 - c) u u^T, written so that a literal axis folds: about
/// z it is [c -s 0; s c 0; 0 0 1], with no half angles and no division.
Value axis_angle_rotation(const Vec& axis, const Expr& angle) {
  const Expr n = call(Fn::Sqrt, {add(add(sq(axis[0]), sq(axis[1])), sq(axis[2]))});
  Vec u;
  for (const Expr& a : axis) u.push_back(div(a, n));
  const Expr c = call(Fn::Cos, {angle}), s = call(Fn::Sin, {angle}), v = sub(constant(1), c);
  Value r{3, 3, Vec(9)};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Expr uu = mul(u[static_cast<std::size_t>(i)], u[static_cast<std::size_t>(j)]);
      Expr x;
      if (i == j) {
        double w = 0.0;
        x = is_const(uu, &w) && w == 1.0 ? constant(1) : add(c, mul(v, uu));
      } else {
        const int k = 3 - i - j;  // [u]x(i, j) = -+u_k
        const Expr skew = (j == (i + 1) % 3) ? neg(u[static_cast<std::size_t>(k)]) : u[static_cast<std::size_t>(k)];
        x = add(mul(s, skew), mul(v, uu));
      }
      r.items[static_cast<std::size_t>(3 * i + j)] = x;
    }
  return r;
}

Value column(Vec items) {
  Value r{static_cast<int>(items.size()), 1, std::move(items)};
  return r;
}

Expr dot_of(const Vec& a, const Vec& b) {
  Expr s = constant(0);
  for (std::size_t i = 0; i < a.size(); ++i) s = add(s, mul(a[i], b[i]));
  return s;
}

Vec cross_of(const Vec& a, const Vec& b) {
  return {sub(mul(a[1], b[2]), mul(a[2], b[1])), sub(mul(a[2], b[0]), mul(a[0], b[2])),
          sub(mul(a[0], b[1]), mul(a[1], b[0]))};
}

/// |q|^2 * rotq(q), row-major: the rotation matrix of q = [w, x, y, z] times
/// w^2 + x^2 + y^2 + z^2 (Hamilton convention, body -> inertial).
Vec scaled_rotation(const Vec& q) {
  const Expr &w = q[0], &x = q[1], &y = q[2], &z = q[3];
  Expr ww = sq(w), xx = sq(x), yy = sq(y), zz = sq(z);
  Expr xy = mul(x, y), xz = mul(x, z), yz = mul(y, z), wx = mul(w, x), wy = mul(w, y), wz = mul(w, z);
  return {sub(sub(add(ww, xx), yy), zz), twice(sub(xy, wz)),  twice(add(xz, wy)),
          twice(add(xy, wz)),  sub(sub(add(ww, yy), xx), zz), twice(sub(yz, wx)),
          twice(sub(xz, wy)),  twice(add(yz, wx)),  sub(sub(add(ww, zz), xx), yy)};
}

/// Hamilton product a (x) b of quaternions [w, x, y, z].
Vec quat_product(const Vec& a, const Vec& b) {
  Vec av{a[1], a[2], a[3]}, bv{b[1], b[2], b[3]};
  Vec c = cross_of(av, bv);
  Vec r{sub(mul(a[0], b[0]), dot_of(av, bv))};
  for (std::size_t i = 0; i < 3; ++i) r.push_back(add(add(mul(a[0], bv[i]), mul(b[0], av[i])), c[i]));
  return r;
}

/// The unit quaternion of the shortest rotation taking +z onto a/|a|, without
/// branches. With b = a/|a| and c = b_z it is u/|u|, u = [1 + c, -b_y, b_x, 0]
/// (|u|^2 = 2(1 + c)). 1 + c is computed without cancellation: as 1 + |c| for
/// c >= 0 and as (b_x^2 + b_y^2)/(1 + |c|) for c < 0. Where b is -z to within
/// 1e-150 rad (b_x^2 + b_y^2 < 1e-300, c < 0) u vanishes and the result is
/// 180 degrees about +x, [0, 1, 0, 0].
Vec arc_quaternion(const Vec& a) {
  Expr r = call(Fn::Sqrt, {dot_of(a, a)});
  Expr bx = div(a[0], r), by = div(a[1], r), c = div(a[2], r);
  Expr h = add(sq(bx), sq(by));
  Expr m = add(constant(1), call(Fn::Abs, {c}));
  Expr up = call(Fn::Step, {c});
  Expr one_plus_c = add(mul(up, m), mul(sub(constant(1), up), div(h, m)));
  Expr d = mul(call(Fn::Step, {sub(constant(1e-300), h)}), call(Fn::Step, {neg(c)}));
  Expr keep = sub(constant(1), d);
  Expr n = call(Fn::Sqrt, {add(add(sq(one_plus_c), h), d)});
  auto part = [&](const Expr& u) { return div(mul(keep, u), n); };
  return {part(one_plus_c), add(part(neg(by)), d), part(bx), constant(0)};
}

const std::map<std::string, Fn> kScalarFns = {
    {"sin", Fn::Sin},   {"cos", Fn::Cos},   {"tan", Fn::Tan},     {"asin", Fn::Asin},
    {"acos", Fn::Acos}, {"atan", Fn::Atan}, {"atan2", Fn::Atan2}, {"sinh", Fn::Sinh},
    {"cosh", Fn::Cosh}, {"tanh", Fn::Tanh}, {"exp", Fn::Exp},     {"log", Fn::Log},
    {"sqrt", Fn::Sqrt}, {"abs", Fn::Abs},   {"sign", Fn::Sign},   {"min", Fn::Min},
    {"max", Fn::Max},     {"heaviside", Fn::Step}, {"select", Fn::Select},
};

/// Lowers an AST expression (names looked up) or a term (refs looked up):
/// one set of rules for both, only the leaves differ.
template <class Ex, class Lookup>
class Lowerer {
 public:
  Lowerer(const Lookup& lookup, Diagnostics& diags) : lookup_(lookup), diags_(diags) {}

  std::optional<Value> run(const Ex& e) {
    switch (e.kind) {
      case Ex::Kind::Number:  // in SI; its unit, if written, for the units check
        return Value::scalar(constant(e.number, e.unit ? units::literal_unit(e.unit->unit.dimension) : -1));
      case Ex::Kind::Unary: {
        auto a = run(*e.args[0]);
        if (!a) return a;
        if (e.op == '-')
          for (Expr& x : a->items) x = neg(x);
        return a;
      }
      case Ex::Kind::Binary: return binary(e);
      case Ex::Kind::Call: return call_fn(e);
      case Ex::Kind::Index: return index(e);
      case Ex::Kind::List: return list(e);
      case Ex::Kind::String:
        diags_.error(e.loc, fmt::format("the string \"{}\" is not a value", e.name),
                     "strings name files, as in flexible = modal(\"arm.mbm\")");
        return std::nullopt;
      default: return leaf(e);
    }
    return std::nullopt;
  }

 private:
  /// A name (AST) or a ref (term).
  std::optional<Value> leaf(const Ex& e) {
    if constexpr (std::is_same_v<Ex, AstExpr>) {
      if (e.name == "t") return Value::scalar(time());
      if (e.name == "pi") return Value::scalar(constant(M_PI));
      return lookup_(e.name, e.loc);
    } else {
      if (e.ref.kind == Ref::Kind::Time) return Value::scalar(time());
      if (e.ref.kind == Ref::Kind::Pi) return Value::scalar(constant(M_PI));
      return lookup_(e);
    }
  }

  std::optional<Value> binary(const Ex& e) {
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

  std::optional<Value> matmul(const Ex& e, const Value& a, const Value& b) {
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

  std::optional<Value> call_fn(const Ex& e) {
    auto it = kFunctions.find(e.name);
    if (it == kFunctions.end()) {
      std::string near = closest_name(e.name, function_names());
      diags_.error(e.loc, fmt::format("unknown function `{}`", e.name),
                   near.empty() ? "functions: sin cos tan atan2 exp log sqrt abs min max step ramp sine diag "
                                  "eye zeros transpose dot cross skew norm hcat vcat rotq quat_mul ..."
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
    if (it->second.shaped) {
      std::vector<Value> vals;
      for (const auto& a : e.args) {
        auto v = run(*a);
        if (!v) return std::nullopt;
        vals.push_back(std::move(*v));
      }
      return shaped_fn(e, vals);
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
    static const std::map<std::string, std::string> kHints = {
        {"eye", "write eye(n), n a constant integer: the n x n identity"},
        {"zeros", "write zeros(rows) for a column of zeros or zeros(rows, columns), with constant integers"},
        {"transpose", "write transpose(M)"},
        {"dot", "write dot(a, b) with two vectors of the same length"},
        {"cross", "write cross(a, b) with two 3-vectors"},
        {"skew", "write skew(v) with a 3-vector v (skew(a) * b is cross(a, b))"},
        {"norm", "write norm(v) with a vector v"},
        {"hcat", "write hcat(A, B, ...) with the same number of rows in every argument"},
        {"vcat", "write vcat(A, B, ...) with the same number of columns in every argument"},
        {"rotq", "write rotq(q) with a quaternion q = [w, x, y, z]"},
        {"quat_rate", "write quat_rate(q) with a quaternion q = [w, x, y, z]"},
        {"quat_mul", "write quat_mul(a, b) with quaternions a, b = [w, x, y, z]"},
        {"quat_conj", "write quat_conj(q) with a quaternion q = [w, x, y, z]"},
        {"quat_axis_angle", "write quat_axis_angle(axis, angle) with a 3-vector axis and a scalar angle"},
        {"rot_axis_angle", "write rot_axis_angle(axis, angle) with a 3-vector axis and a scalar angle"},
        {"quat_arc", "write quat_arc(a) with a nonzero 3-vector a"},
        {"bryant", "write bryant(q) with a quaternion q = [w, x, y, z]"},
        {"jacobian", "write jacobian(f, x): f a vector of expressions, x a vector of model variables"},
        {"partial_t", "write partial_t(f): the explicit time derivative of f (variables held fixed)"},
        {"table", "write table(x, [[x1, y1], [x2, y2], ...]): y linear between the points (x increasing), constant outside"},
    };
    if (auto h = kHints.find(fn); h != kHints.end()) return h->second;
    if (fn == "step") return "write step(t0) or step(t0, height)";
    if (fn == "ramp") return "write ramp(t0) or ramp(t0, slope)";
    if (fn == "sine") return "write sine(amplitude, frequency_hz) or sine(amplitude, frequency_hz, phase_rad)";
    if (fn == "atan2") return "write atan2(y, x)";
    if (fn == "min" || fn == "max") return fmt::format("write {}(a, b)", fn);
    return fmt::format("write {}(x)", fn);
  }

  // ---- shaped functions ---------------------------------------------------------

  /// The items of argument k of call e if it is a vector (n x 1 or 1 x n) of
  /// length `len` (any length if len < 0); else reports `what` and returns nullopt.
  std::optional<Vec> vector_arg(const Ex& e, const std::vector<Value>& args, std::size_t k, int len,
                                const std::string& what) {
    const Value& v = args[k];
    if (v.is_vector() && (len < 0 || v.length() == len)) return v.items;
    std::string where = e.args.size() == 1 ? "its argument" : fmt::format("argument {}", k + 1);
    diags_.error(e.args[k]->loc, fmt::format("`{}` expects {} as {}, this is {}", e.name, what, where, v.shape()),
                 call_hint(e.name));
    return std::nullopt;
  }
  std::optional<Vec> quaternion_arg(const Ex& e, const std::vector<Value>& args, std::size_t k) {
    return vector_arg(e, args, k, 4, "a quaternion (a 4-vector [w, x, y, z])");
  }

  /// Argument k as a constant integer in 1..kMaxDimension.
  std::optional<int> dimension_arg(const Ex& e, const std::vector<Value>& args, std::size_t k) {
    double c = 0;
    const Value& v = args[k];
    if (v.is_scalar() && is_const(v.items[0], &c) && c == std::floor(c) && c >= 1 && c <= kMaxDimension)
      return static_cast<int>(c);
    std::string got = !v.is_scalar()                     ? fmt::format("this is {}", v.shape())
                      : !is_const(v.items[0], &c)        ? "this is not a constant: a parameter can change at run time "
                                                           "(--set), a size cannot"
                                                         : fmt::format("this is {}", c);
    diags_.error(e.args[k]->loc,
                 fmt::format("`{}` needs a constant integer from 1 to {} here; {}", e.name, kMaxDimension, got),
                 call_hint(e.name));
    return std::nullopt;
  }

  /// table(x, [[x1, y1], ..., [xn, yn]]): y piecewise linear in x through the
  /// points (x increasing), y1 before x1 and yn after xn, written as
  /// y1 + sum_k s_k (max(0, x - x_k) - max(0, x - x_k+1)): the kinks are
  /// exact, and a table of time is a chain of time events (the max of a
  /// function of time), which the integrators locate.
  std::optional<Value> table(const Ex& e, const std::vector<Value>& args) {
    if (!args[0].is_scalar()) {
      diags_.error(e.args[0]->loc, fmt::format("`table` looks up a scalar, this is {}", args[0].shape()), call_hint("table"));
      return std::nullopt;
    }
    const Value& pts = args[1];
    if (pts.cols != 2 || pts.rows < 2 || pts.rows > kMaxTablePoints) {
      diags_.error(e.args[1]->loc,
                   fmt::format("the points of `table` are {}: a list of 2 to {} pairs [x, y] is needed", pts.shape(), kMaxTablePoints),
                   call_hint("table"));
      return std::nullopt;
    }
    for (int k = 0; k + 1 < pts.rows; ++k) {
      double a = 0, b = 0;
      if (is_const(pts.at(k, 0), &a) && is_const(pts.at(k + 1, 0), &b) && !(b > a)) {
        diags_.error(e.args[1]->loc, fmt::format("the x of `table`'s points must increase: point {} has x = {}, point {} x = {}", k + 1, a, k + 2, b),
                     call_hint("table"));
        return std::nullopt;
      }
    }
    const Expr& x = args[0].items[0];
    Expr y = pts.at(0, 1);
    for (int k = 0; k + 1 < pts.rows; ++k) {
      const Expr slope = div(sub(pts.at(k + 1, 1), pts.at(k, 1)), sub(pts.at(k + 1, 0), pts.at(k, 0)));
      y = add(y, mul(slope, sub(call(Fn::Max, {constant(0), sub(x, pts.at(k, 0))}),
                                call(Fn::Max, {constant(0), sub(x, pts.at(k + 1, 0))}))));
    }
    return Value::scalar(y);
  }

  std::optional<Value> shaped_fn(const Ex& e, const std::vector<Value>& args) {
    const std::string& f = e.name;
    if (f == "eye" || f == "zeros") {
      auto rows = dimension_arg(e, args, 0);
      if (!rows) return std::nullopt;
      int cols = f == "eye" ? *rows : 1;
      if (args.size() > 1) {
        auto c = dimension_arg(e, args, 1);
        if (!c) return std::nullopt;
        cols = *c;
      }
      Value r{*rows, cols, {}};
      for (int i = 0; i < *rows; ++i)
        for (int j = 0; j < cols; ++j) r.items.push_back(constant(f == "eye" && i == j ? 1 : 0));
      return r;
    }
    if (f == "table") return table(e, args);
    if (f == "frozen") {  // x, each entry with derivative 0
      Value r = args[0];
      for (Expr& x : r.items) x = call(Fn::Frozen, {x});
      return r;
    }
    if (f == "transpose") {
      const Value& m = args[0];
      Value r{m.cols, m.rows, {}};
      for (int i = 0; i < m.cols; ++i)
        for (int j = 0; j < m.rows; ++j) r.items.push_back(m.at(j, i));
      return r;
    }
    if (f == "dot") {
      auto a = vector_arg(e, args, 0, -1, "a vector");
      if (!a) return std::nullopt;
      auto b = vector_arg(e, args, 1, static_cast<int>(a->size()), fmt::format("a {}-vector (like argument 1)", a->size()));
      if (!b) return std::nullopt;
      return Value::scalar(dot_of(*a, *b));
    }
    if (f == "norm") {
      auto a = vector_arg(e, args, 0, -1, "a vector");
      if (!a) return std::nullopt;
      return Value::scalar(call(Fn::Sqrt, {dot_of(*a, *a)}));
    }
    if (f == "cross") {
      auto a = vector_arg(e, args, 0, 3, "a 3-vector");
      if (!a) return std::nullopt;
      auto b = vector_arg(e, args, 1, 3, "a 3-vector");
      if (!b) return std::nullopt;
      return column(cross_of(*a, *b));
    }
    if (f == "skew") {
      auto v = vector_arg(e, args, 0, 3, "a 3-vector");
      if (!v) return std::nullopt;
      const Vec& a = *v;
      Expr o = constant(0);
      return Value{3, 3, {o, neg(a[2]), a[1], a[2], o, neg(a[0]), neg(a[1]), a[0], o}};
    }
    if (f == "hcat" || f == "vcat") return concatenate(e, args, f == "hcat");
    if (f == "rotq") {
      auto q = quaternion_arg(e, args, 0);
      if (!q) return std::nullopt;
      Expr n2 = dot_of(*q, *q);
      Value r{3, 3, scaled_rotation(*q)};
      for (Expr& x : r.items) x = div(x, n2);
      return r;
    }
    if (f == "quat_rate") {  // q' = E omega = 1/2 q (x) [0, omega], omega in body coordinates
      auto q = quaternion_arg(e, args, 0);
      if (!q) return std::nullopt;
      auto h = [](const Expr& x) { return mul(constant(0.5), x); };
      const Expr &w = (*q)[0], &x = (*q)[1], &y = (*q)[2], &z = (*q)[3];
      return Value{4, 3, {h(neg(x)), h(neg(y)), h(neg(z)),  //
                          h(w), h(neg(z)), h(y),            //
                          h(z), h(w), h(neg(x)),            //
                          h(neg(y)), h(x), h(w)}};
    }
    if (f == "quat_mul") {
      auto a = quaternion_arg(e, args, 0);
      if (!a) return std::nullopt;
      auto b = quaternion_arg(e, args, 1);
      if (!b) return std::nullopt;
      return column(quat_product(*a, *b));
    }
    if (f == "quat_conj") {
      auto q = quaternion_arg(e, args, 0);
      if (!q) return std::nullopt;
      return column({(*q)[0], neg((*q)[1]), neg((*q)[2]), neg((*q)[3])});
    }
    if (f == "quat_axis_angle" || f == "rot_axis_angle") {
      auto axis = vector_arg(e, args, 0, 3, "a 3-vector (the axis)");
      if (!axis) return std::nullopt;
      if (!args[1].is_scalar()) {
        diags_.error(e.args[1]->loc, fmt::format("`{}` expects a scalar angle as argument 2, this is {}", f, args[1].shape()),
                     call_hint(f));
        return std::nullopt;
      }
      const Expr& angle = args[1].items[0];
      if (f == "rot_axis_angle") return axis_angle_rotation(*axis, angle);
      Expr half = mul(constant(0.5), angle);
      Expr s = div(call(Fn::Sin, {half}), call(Fn::Sqrt, {dot_of(*axis, *axis)}));
      return column({call(Fn::Cos, {half}), mul((*axis)[0], s), mul((*axis)[1], s), mul((*axis)[2], s)});
    }
    if (f == "quat_arc") {
      auto a = vector_arg(e, args, 0, 3, "a 3-vector");
      if (!a) return std::nullopt;
      return column(arc_quaternion(*a));
    }
    if (f == "bryant") {  // rotq(q) = Rx(phi) Ry(theta) Rz(psi) -> [phi, theta, psi]
      auto q = quaternion_arg(e, args, 0);
      if (!q) return std::nullopt;
      Vec a = scaled_rotation(*q);  // |q|^2 A: atan2 needs no division
      Expr s = div(a[2], dot_of(*q, *q));
      s = call(Fn::Max, {constant(-1), call(Fn::Min, {constant(1), s})});  // rounding may leave [-1, 1]
      return column({call(Fn::Atan2, {neg(a[5]), a[8]}), call(Fn::Asin, {s}), call(Fn::Atan2, {neg(a[1]), a[0]})});
    }
    if (f == "jacobian") {
      auto fv = vector_arg(e, args, 0, -1, "a vector of expressions");
      if (!fv) return std::nullopt;
      auto xv = vector_arg(e, args, 1, -1, "a vector of model variables");
      if (!xv) return std::nullopt;
      for (const Expr& x : *xv)
        if (x->op != Op::Var) {
          diags_.error(e.args[1]->loc, "jacobian's second argument must be model variables (e.g. a C element's q)",
                       call_hint(f));
          return std::nullopt;
        }
      Value r{static_cast<int>(fv->size()), static_cast<int>(xv->size()), {}};
      for (const Expr& fi : *fv)
        for (const Expr& x : *xv) r.items.push_back(diff_var(fi, x->id));
      return r;
    }
    if (f == "partial_t") {  // d/dt with the variables held fixed (a prescribed motion's rate)
      Value r = args[0];
      for (Expr& x : r.items) x = diff_time(x);
      return r;
    }
    diags_.error(e.loc, fmt::format("internal error: no lowering for `{}`", f));
    return std::nullopt;
  }

  std::optional<Value> concatenate(const Ex& e, const std::vector<Value>& args, bool side_by_side) {
    const Value& first = args[0];
    int rows = first.rows, cols = first.cols;
    for (std::size_t k = 1; k < args.size(); ++k) {
      const Value& v = args[k];
      if (side_by_side ? v.rows != first.rows : v.cols != first.cols) {
        diags_.error(e.args[k]->loc,
                     fmt::format("`{}` of {} and {}: the {} counts differ ({} and {})", e.name, first.shape(), v.shape(),
                                 side_by_side ? "row" : "column", side_by_side ? first.rows : first.cols,
                                 side_by_side ? v.rows : v.cols),
                     call_hint(e.name));
        return std::nullopt;
      }
      (side_by_side ? cols : rows) += side_by_side ? v.cols : v.rows;
    }
    Value r{rows, cols, {}};
    if (side_by_side) {
      for (int i = 0; i < rows; ++i)
        for (const Value& v : args)
          for (int j = 0; j < v.cols; ++j) r.items.push_back(v.at(i, j));
    } else {
      for (const Value& v : args) r.items.insert(r.items.end(), v.items.begin(), v.items.end());
    }
    return r;
  }

  std::optional<Value> index(const Ex& e) {
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
      if (std::abs(c) > kMaxDimension) {  // no shape is this large, and an int could not hold it
        diags_.error(e.args[k]->loc, fmt::format("index {} is out of range for {}", c, base->shape()),
                     fmt::format("no value has more than {} rows or columns", kMaxDimension));
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

  std::optional<Value> list(const Ex& e) {
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

  const Lookup& lookup_;
  Diagnostics& diags_;
};

}  // namespace

std::optional<Value> lower(const AstExpr& e, const NameLookup& lookup, Diagnostics& diags) {
  Lowerer<AstExpr, NameLookup> l(lookup, diags);
  return l.run(e);
}

std::optional<Value> lower(const Term& e, const RefLookup& lookup, Diagnostics& diags) {
  Lowerer<Term, RefLookup> l(lookup, diags);
  return l.run(e);
}

std::vector<std::string> function_names() {
  std::vector<std::string> names;
  for (const auto& [n, info] : kFunctions) names.push_back(n);
  return names;
}

}  // namespace mbgc::ir
