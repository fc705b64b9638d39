// Unit tests for ir/expr: smart-constructor folding and identities, structural
// hashing/equality, differentiation (checked against finite differences),
// substitution, affine decomposition and both printers.
#include "ir/expr.hpp"
#include "units/unit.hpp"

#include "cpp_ops_text.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace {

using namespace mbgc::ir;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Vars 0..5 print as a, b, c, x, y, z; params 0, 1 as p, q.
const char* const kVarNames[] = {"a", "b", "c", "x", "y", "z"};
const char* const kParamNames[] = {"p", "q"};
enum : int { A = 0, B = 1, C = 2, X = 3, Y = 4, Z = 5 };
enum : int { P = 0, Q = 1 };

Namer names() {
  Namer n;
  n.var = [](int id) { return std::string(kVarNames[id]); };
  n.param = [](int id) { return std::string(kParamNames[id]); };
  return n;
}

std::string str(const Expr& e) { return to_string(e, names()); }
std::string cpp(const Expr& e) { return to_cpp(e, names()); }

Expr k(double v) { return constant(v); }
Expr fn(Fn f, Expr a) { return call(f, {std::move(a)}); }
Expr fn(Fn f, Expr a, Expr b) { return call(f, {std::move(a), std::move(b)}); }

// ---- a tiny evaluator ---------------------------------------------------------

struct Env {
  std::map<int, double> vars;
  std::map<int, double> params;
  double t = 0.0;
};

// `degenerate`, if given, is set when the evaluation goes through a value where
// IEEE corner cases decide the result (division by zero, 0^x, atan2 of zeros,
// a non-finite intermediate): there the simplifications may legitimately differ
// (x*0 = 0, -0.0 = 0.0, ...) and finite differences mean nothing.
double eval(const Expr& e, const Env& env, bool* degenerate = nullptr);

double eval_node(const Expr& e, const Env& env, bool* degenerate) {
  auto ev = [&](int i) { return eval(e->args[static_cast<std::size_t>(i)], env, degenerate); };
  auto flag = [&](bool c) {
    if (c && degenerate) *degenerate = true;
  };
  switch (e->op) {
    case Op::Const: return e->value;
    case Op::Param: return env.params.at(e->id);
    case Op::Var: return env.vars.at(e->id);
    case Op::Time: return env.t;
    case Op::Neg: return -ev(0);
    case Op::Add: return ev(0) + ev(1);
    case Op::Sub: return ev(0) - ev(1);
    case Op::Mul: return ev(0) * ev(1);
    case Op::Div: {
      const double u = ev(0), v = ev(1);
      flag(v == 0.0);
      return u / v;
    }
    case Op::Pow: {
      const double u = ev(0), v = ev(1);
      flag(u == 0.0);
      return std::pow(u, v);
    }
    case Op::Der: throw std::logic_error("eval: der");
    case Op::Call: break;
  }
  const double x = ev(0);
  const double y = e->args.size() > 1 ? ev(1) : 0.0;
  if (e->fn == Fn::Atan2) flag(x == 0.0 || y == 0.0);
  switch (e->fn) {
    case Fn::Sin: return std::sin(x);
    case Fn::Cos: return std::cos(x);
    case Fn::Tan: return std::tan(x);
    case Fn::Asin: return std::asin(x);
    case Fn::Acos: return std::acos(x);
    case Fn::Atan: return std::atan(x);
    case Fn::Atan2: return std::atan2(x, y);
    case Fn::Sinh: return std::sinh(x);
    case Fn::Cosh: return std::cosh(x);
    case Fn::Tanh: return std::tanh(x);
    case Fn::Exp: return std::exp(x);
    case Fn::Log: return std::log(x);
    case Fn::Sqrt: return std::sqrt(x);
    case Fn::Abs: return std::fabs(x);
    case Fn::Sign: return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
    case Fn::Min: return std::fmin(x, y);
    case Fn::Max: return std::fmax(x, y);
    case Fn::Step: return x >= 0 ? 1.0 : 0.0;
    case Fn::Select: return x >= 0 ? 1.0 : 0.0;
    case Fn::Frozen: return x;
  }
  throw std::logic_error("eval: bad fn");
}

double eval(const Expr& e, const Env& env, bool* degenerate) {
  const double v = eval_node(e, env, degenerate);
  if (degenerate && !std::isfinite(v)) *degenerate = true;
  return v;
}

// Central difference of e with respect to var `id` (or t when id < 0).
double central_diff(const Expr& e, Env env, int id, double h) {
  double& x = id < 0 ? env.t : env.vars.at(id);
  const double x0 = x;
  x = x0 + h;
  const double fp = eval(e, env);
  x = x0 - h;
  const double fm = eval(e, env);
  return (fp - fm) / (2 * h);
}

::testing::AssertionResult derivative_matches(const Expr& e, const Expr& de, const Env& env,
                                              int id) {
  const double d = eval(de, env);
  const double fd = central_diff(e, env, id, 1e-6);
  if (std::isfinite(d) && std::fabs(d - fd) <= 1e-6 * (1 + std::fabs(fd)))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "d/d" << (id < 0 ? "t" : kVarNames[id]) << " " << str(e) << " = " << str(de)
         << ": symbolic " << d << ", finite difference " << fd;
}

// ---- a tiny parser for the model syntax printed by to_string ---------------------

class Parser {
 public:
  explicit Parser(std::string s) : s_(std::move(s)) {}

  Expr parse() {
    Expr e = expr();
    skip();
    if (pos_ != s_.size()) fail("trailing text");
    return e;
  }

 private:
  [[noreturn]] void fail(const std::string& why) {
    throw std::runtime_error("parse error (" + why + ") at " + std::to_string(pos_) + " in '" +
                             s_ + "'");
  }
  void skip() {
    while (pos_ < s_.size() && s_[pos_] == ' ') ++pos_;
  }
  bool eat(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!eat(c)) fail(std::string("expected ") + c);
  }
  Expr expr() {
    Expr e = term();
    for (;;) {
      if (eat('+')) e = add(e, term());
      else if (eat('-')) e = sub(e, term());
      else return e;
    }
  }
  Expr term() {
    Expr e = unary();
    for (;;) {
      if (eat('*')) e = mul(e, unary());
      else if (eat('/')) e = div(e, unary());
      else return e;
    }
  }
  Expr unary() {
    if (eat('-')) return neg(unary());
    return power();
  }
  Expr power() {  // right-associative, binds tighter than unary minus on its left
    Expr base = primary();
    if (eat('^')) return pow(base, unary());
    return base;
  }
  Expr primary() {
    skip();
    if (eat('(')) {
      Expr e = expr();
      expect(')');
      return e;
    }
    if (pos_ >= s_.size()) fail("unexpected end");
    const char c = s_[pos_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* start = s_.c_str() + pos_;
      char* end = nullptr;
      const double v = std::strtod(start, &end);
      pos_ += static_cast<std::size_t>(end - start);
      return constant(v);
    }
    if (!std::isalpha(static_cast<unsigned char>(c))) fail("unexpected character");
    std::string id;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_'))
      id += s_[pos_++];
    if (eat('(')) {
      std::vector<Expr> args{expr()};
      while (eat(',')) args.push_back(expr());
      expect(')');
      if (id == "der") return der(args.at(0));
      for (int f = 0; f <= static_cast<int>(Fn::Step); ++f)
        if (id == fn_name(static_cast<Fn>(f))) return call(static_cast<Fn>(f), std::move(args));
      fail("unknown function " + id);
    }
    if (id == "t") return time();
    if (id == "inf") return constant(kInf);
    if (id == "nan") return constant(kNaN);
    for (int i = 0; i < 6; ++i)
      if (id == kVarNames[i]) return var(i);
    for (int i = 0; i < 2; ++i)
      if (id == kParamNames[i]) return param(i);
    fail("unknown name " + id);
  }

  std::string s_;
  std::size_t pos_ = 0;
};

Expr parse(const std::string& s) { return Parser(s).parse(); }

// ---- raw (unsimplified) trees for property tests ------------------------------

Expr raw(Op op, std::vector<Expr> args, double value = 0.0, int id = -1, Fn f = Fn::Sin) {
  auto* n = new Node();
  n->op = op;
  n->args = Operands(std::move(args));
  n->value = value;
  n->id = id;
  n->fn = f;
  return Expr(n);
}

// Rebuild a raw tree bottom-up through the smart constructors.
Expr smart(const Expr& r) {
  std::vector<Expr> a;
  for (const Expr& x : r->args) a.push_back(smart(x));
  switch (r->op) {
    case Op::Const: return constant(r->value);
    case Op::Param: return param(r->id);
    case Op::Var: return var(r->id);
    case Op::Time: return time();
    case Op::Neg: return neg(a[0]);
    case Op::Add: return add(a[0], a[1]);
    case Op::Sub: return sub(a[0], a[1]);
    case Op::Mul: return mul(a[0], a[1]);
    case Op::Div: return div(a[0], a[1]);
    case Op::Pow: return pow(a[0], a[1]);
    case Op::Call: return call(r->fn, a);
    case Op::Der: return der(a[0]);
  }
  return nullptr;
}

class Random {
 public:
  explicit Random(std::uint64_t seed) : rng_(seed) {}
  unsigned pick(unsigned n) { return static_cast<unsigned>(rng_() % n); }
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  }

  // Random raw tree over vars a, b, param p and t. `smooth` leaves out the
  // functions with kinks or jumps and keeps the domain-restricted ones guarded.
  Expr tree(int depth, bool smooth = false) {
    if (depth == 0 || pick(5) == 0) return leaf();
    switch (pick(9)) {
      case 0: return raw(Op::Neg, {tree(depth - 1, smooth)});
      case 1: return raw(Op::Add, {tree(depth - 1, smooth), tree(depth - 1, smooth)});
      case 2: return raw(Op::Sub, {tree(depth - 1, smooth), tree(depth - 1, smooth)});
      case 3: return raw(Op::Mul, {tree(depth - 1, smooth), tree(depth - 1, smooth)});
      case 4: return raw(Op::Div, {tree(depth - 1, smooth), tree(depth - 1, smooth)});
      case 5: {
        static const double exps[] = {2, 3, 0.5, -1, 1, 0, 1.5};
        Expr b = pick(3) ? raw(Op::Const, {}, exps[pick(7)]) : tree(depth - 1, smooth);
        return raw(Op::Pow, {tree(depth - 1, smooth), b});
      }
      default: {
        Fn f = static_cast<Fn>(pick(static_cast<unsigned>(Fn::Step) + 1));
        if (smooth && (f == Fn::Abs || f == Fn::Sign || f == Fn::Step || f == Fn::Min ||
                       f == Fn::Max))
          f = Fn::Atan;
        std::vector<Expr> args;
        for (int i = 0; i < arity(f); ++i) args.push_back(tree(depth - 1, smooth));
        return raw(Op::Call, std::move(args), 0.0, -1, f);
      }
    }
  }

  Env env() {
    Env e;
    e.vars[A] = uniform(-2, 2);
    e.vars[B] = uniform(-2, 2);
    e.params[P] = 1.7;
    e.t = uniform(0, 3);
    return e;
  }

 private:
  Expr leaf() {
    static const double consts[] = {0, 1, 2, 0.5, 3, -1, -2.5, 0.1, 1e-06, 60};
    switch (pick(6)) {
      case 0: return raw(Op::Var, {}, 0.0, A);
      case 1: return raw(Op::Var, {}, 0.0, B);
      case 2: return raw(Op::Param, {}, 0.0, P);
      case 3: return raw(Op::Time, {});
      default: return raw(Op::Const, {}, consts[pick(10)]);
    }
  }

  std::mt19937_64 rng_;
};

bool same_value(double u, double v, double rel) {
  if (std::isnan(u) || std::isnan(v)) return std::isnan(u) && std::isnan(v);
  if (std::isinf(u) || std::isinf(v)) return u == v;
  return std::fabs(u - v) <= rel * (1 + std::fabs(u));
}

// ---- folding --------------------------------------------------------------------

TEST(ExprFold, ALiteralsUnitStaysUntilItIsFolded) {
  const int m = mbgc::units::literal_unit(mbgc::units::dim::length());
  const Expr mm = constant(0.002, m);  // `2 {mm}`
  EXPECT_NE(mm, constant(0.002));      // not the plain number: the units check reads it
  EXPECT_FALSE(equal(mm, constant(0.002)));
  EXPECT_EQ(mm, constant(0.002, m));   // one node per value and unit
  EXPECT_EQ(neg(mm)->id, m);           // `-2 {mm}`
  EXPECT_EQ(neg(mm)->value, -0.002);
  EXPECT_EQ(constant(0.0, m)->id, m);  // `0 {m}` is not the plain zero
  EXPECT_TRUE(is_zero(constant(0.0, m)));
  EXPECT_EQ(mul(mm, constant(3))->id, -1);  // folded: a number again
  EXPECT_EQ(mul(mm, constant(3))->value, 0.006);
  EXPECT_EQ(to_cpp(mul(mm, var(0)), Namer{}), "0.002 * v0");          // C++: as any constant
  EXPECT_EQ(to_string(mul(mm, var(0)), Namer{}), "0.002 {m}*v0");     // a dump or a diagnostic: with its unit, in SI
}

TEST(ExprFold, ArithmeticOfConstants) {
  double v = 0;
  ASSERT_TRUE(is_const(add(k(2), k(3)), &v));
  EXPECT_EQ(v, 5);
  ASSERT_TRUE(is_const(sub(k(2), k(3)), &v));
  EXPECT_EQ(v, -1);
  ASSERT_TRUE(is_const(mul(k(2), k(3)), &v));
  EXPECT_EQ(v, 6);
  ASSERT_TRUE(is_const(div(k(3), k(4)), &v));
  EXPECT_EQ(v, 0.75);
  ASSERT_TRUE(is_const(pow(k(2), k(10)), &v));
  EXPECT_EQ(v, 1024);
  ASSERT_TRUE(is_const(pow(k(2), k(0.5)), &v));
  EXPECT_EQ(v, std::pow(2.0, 0.5));
  ASSERT_TRUE(is_const(neg(k(2)), &v));
  EXPECT_EQ(v, -2);
  EXPECT_FALSE(is_const(var(X)));
  EXPECT_FALSE(is_const(param(P)));
  EXPECT_FALSE(is_const(time()));
}

TEST(ExprFold, CallsOfConstants) {
  double v = 0;
  ASSERT_TRUE(is_const(fn(Fn::Sin, k(0.5)), &v));
  EXPECT_EQ(v, std::sin(0.5));
  ASSERT_TRUE(is_const(fn(Fn::Atan2, k(1), k(-2)), &v));
  EXPECT_EQ(v, std::atan2(1.0, -2.0));
  ASSERT_TRUE(is_const(fn(Fn::Min, k(1), k(-2)), &v));
  EXPECT_EQ(v, -2);
  ASSERT_TRUE(is_const(fn(Fn::Max, k(1), k(-2)), &v));
  EXPECT_EQ(v, 1);
  ASSERT_TRUE(is_const(fn(Fn::Abs, k(-3)), &v));
  EXPECT_EQ(v, 3);
  ASSERT_TRUE(is_const(fn(Fn::Sqrt, k(9)), &v));
  EXPECT_EQ(v, 3);
  ASSERT_TRUE(is_const(fn(Fn::Exp, k(0)), &v));
  EXPECT_EQ(v, 1);
  ASSERT_TRUE(is_const(fn(Fn::Step, k(0)), &v));
  EXPECT_EQ(v, 1);
  ASSERT_TRUE(is_const(fn(Fn::Step, k(-1e-300)), &v));
  EXPECT_EQ(v, 0);
  ASSERT_TRUE(is_const(fn(Fn::Step, k(2)), &v));
  EXPECT_EQ(v, 1);
  ASSERT_TRUE(is_const(fn(Fn::Sign, k(-0.5)), &v));
  EXPECT_EQ(v, -1);
  ASSERT_TRUE(is_const(fn(Fn::Sign, k(0)), &v));
  EXPECT_EQ(v, 0);
  ASSERT_TRUE(is_const(fn(Fn::Sign, k(7)), &v));
  EXPECT_EQ(v, 1);
  // every function folds, with the evaluator's semantics
  for (int f = 0; f <= static_cast<int>(Fn::Select); ++f) {  // (Frozen's derivative is 0 by design)
    const Fn ff = static_cast<Fn>(f);
    std::vector<Expr> args{k(0.3)};
    if (arity(ff) == 2) args.push_back(k(0.7));
    const Expr raw_call = raw(Op::Call, args, 0.0, -1, ff);
    const Expr e = call(ff, args);
    ASSERT_TRUE(is_const(e, &v)) << fn_name(ff);
    EXPECT_EQ(v, eval(raw_call, Env{})) << fn_name(ff);
  }
}

TEST(ExprFold, PartialConstantsDoNotFoldCalls) {
  EXPECT_EQ(fn(Fn::Atan2, var(Y), k(1))->op, Op::Call);
  EXPECT_EQ(fn(Fn::Sin, var(X))->op, Op::Call);
}

TEST(ExprFold, DivisionByConstantZeroIsKept) {
  const Expr e = div(k(1), k(0));
  EXPECT_EQ(e->op, Op::Div);
  EXPECT_EQ(div(k(0), k(0))->op, Op::Div);
  EXPECT_EQ(div(var(X), k(0))->op, Op::Div);
  EXPECT_EQ(div(var(X), k(-0.0))->op, Op::Div);
  EXPECT_EQ(str(e), "1/0");
  // signs still float out of a division by zero
  EXPECT_TRUE(equal(div(neg(var(X)), k(0)), neg(div(var(X), k(0)))));
  EXPECT_TRUE(equal(div(k(-2), k(0)), neg(div(k(2), k(0)))));
}

TEST(ExprFold, ConstantNormalisation) {
  EXPECT_TRUE(equal(k(-0.0), k(0.0)));
  EXPECT_FALSE(std::signbit(k(-0.0)->value));
  EXPECT_TRUE(equal(k(kNaN), k(-kNaN)));
  EXPECT_TRUE(equal(k(kNaN), mul(k(0), k(kInf))));
  EXPECT_TRUE(is_zero(k(-0.0)));
  EXPECT_TRUE(is_one(k(1)));
  EXPECT_FALSE(is_one(k(-1)));
  EXPECT_FALSE(is_zero(var(X)));
}

TEST(ExprFold, Der) {
  EXPECT_TRUE(is_zero(der(k(3))));
  EXPECT_TRUE(is_zero(der(param(P))));
  EXPECT_TRUE(is_one(der(time())));
  const Expr d = der(var(X));
  EXPECT_EQ(d->op, Op::Der);
  EXPECT_TRUE(equal(d->args[0], var(X)));
  EXPECT_EQ(der(mul(k(2), var(X)))->op, Op::Der);  // no expansion
}

TEST(ExprFold, ArityAndNames) {
  EXPECT_EQ(arity(Fn::Atan2), 2);
  EXPECT_EQ(arity(Fn::Min), 2);
  EXPECT_EQ(arity(Fn::Max), 2);
  for (Fn f : {Fn::Sin, Fn::Cos, Fn::Tan, Fn::Asin, Fn::Acos, Fn::Atan, Fn::Sinh, Fn::Cosh,
               Fn::Tanh, Fn::Exp, Fn::Log, Fn::Sqrt, Fn::Abs, Fn::Sign, Fn::Step})
    EXPECT_EQ(arity(f), 1) << fn_name(f);
  EXPECT_STREQ(fn_name(Fn::Atan2), "atan2");
  EXPECT_STREQ(fn_name(Fn::Step), "heaviside");
  EXPECT_STREQ(fn_name(Fn::Abs), "abs");
  EXPECT_STREQ(fn_name(Fn::Sign), "sign");
  std::unordered_set<std::string> seen;
  for (int f = 0; f <= static_cast<int>(Fn::Step); ++f)
    EXPECT_TRUE(seen.insert(fn_name(static_cast<Fn>(f))).second);
  EXPECT_THROW(call(Fn::Sin, {var(X), var(Y)}), std::invalid_argument);
  EXPECT_THROW(call(Fn::Atan2, {var(X)}), std::invalid_argument);
}

// ---- identities -----------------------------------------------------------------

TEST(ExprIdentity, PythagoreanSumOfSquaresIsOne) {
  const Expr c = call(Fn::Cos, {var(X)}), s = call(Fn::Sin, {var(X)});
  EXPECT_TRUE(is_one(add(mul(c, c), mul(s, s))));
  EXPECT_TRUE(is_one(add(mul(s, s), mul(c, c))));
  // not for different arguments, nor for one function twice, nor for a difference
  const Expr s2 = call(Fn::Sin, {var(Y)});
  EXPECT_FALSE(is_one(add(mul(c, c), mul(s2, s2))));
  EXPECT_FALSE(is_one(add(mul(c, c), mul(c, c))));
  EXPECT_FALSE(is_one(sub(mul(c, c), mul(s, s))));
  EXPECT_FALSE(is_one(add(mul(c, s), mul(s, c))));
}

TEST(ExprIdentity, AddSub) {
  const Expr x = var(X), y = var(Y);
  EXPECT_EQ(add(x, k(0)), x);
  EXPECT_EQ(add(k(0), x), x);
  EXPECT_EQ(sub(x, k(0)), x);
  EXPECT_TRUE(equal(sub(k(0), x), neg(x)));
  EXPECT_EQ(sub(k(0), x)->op, Op::Neg);
  EXPECT_TRUE(is_zero(sub(x, var(X))));  // structural, not pointer, equality
  EXPECT_TRUE(is_zero(sub(fn(Fn::Sin, mul(x, y)), fn(Fn::Sin, mul(var(X), var(Y))))));
  EXPECT_FALSE(is_zero(sub(x, y)));
  EXPECT_TRUE(equal(add(x, neg(y)), sub(x, y)));
  EXPECT_TRUE(equal(sub(x, neg(y)), add(x, y)));
  EXPECT_TRUE(equal(add(x, k(-2)), sub(x, k(2))));
  EXPECT_TRUE(equal(sub(x, k(-2)), add(x, k(2))));
  EXPECT_EQ(add(x, y)->op, Op::Add);
  EXPECT_EQ(sub(x, y)->op, Op::Sub);
}

TEST(ExprIdentity, MulDiv) {
  const Expr x = var(X), y = var(Y);
  EXPECT_EQ(mul(x, k(1)), x);
  EXPECT_EQ(mul(k(1), x), x);
  EXPECT_TRUE(is_zero(mul(x, k(0))));
  EXPECT_TRUE(is_zero(mul(k(0), x)));
  EXPECT_TRUE(equal(mul(x, k(-1)), neg(x)));
  EXPECT_TRUE(equal(mul(k(-1), x), neg(x)));
  EXPECT_EQ(div(x, k(1)), x);
  EXPECT_TRUE(is_zero(div(k(0), x)));
  EXPECT_EQ(div(x, var(X))->op, Op::Div);  // a/a is deliberately not folded: x may be 0
  const Expr denom = add(k(1), mul(x, x));  // 1 + x^2 is never 0: its quotient by itself is 1
  EXPECT_TRUE(is_one(div(denom, add(k(1), mul(x, x)))));
  EXPECT_EQ(div(add(k(1), y), add(k(1), y))->op, Op::Div);  // 1 + y may be 0
  EXPECT_TRUE(equal(div(x, k(-1)), neg(x)));
}

TEST(ExprIdentity, NegPow) {
  const Expr x = var(X);
  EXPECT_EQ(neg(neg(x)), x);
  EXPECT_EQ(neg(x)->op, Op::Neg);
  EXPECT_EQ(pow(x, k(1)), x);
  EXPECT_TRUE(is_one(pow(x, k(0))));
  EXPECT_EQ(pow(x, k(2))->op, Op::Pow);
}

TEST(ExprIdentity, SignsFloatOutward) {
  const Expr x = var(X), y = var(Y);
  EXPECT_TRUE(equal(mul(neg(x), neg(y)), mul(x, y)));
  EXPECT_TRUE(equal(mul(neg(x), y), neg(mul(x, y))));
  EXPECT_TRUE(equal(mul(x, neg(y)), neg(mul(x, y))));
  EXPECT_TRUE(equal(div(neg(x), neg(y)), div(x, y)));
  EXPECT_TRUE(equal(div(neg(x), y), neg(div(x, y))));
  EXPECT_TRUE(equal(div(x, neg(y)), neg(div(x, y))));
  // negative constant factors too, so -2*x has one representation
  EXPECT_TRUE(equal(mul(k(-2), x), neg(mul(k(2), x))));
  EXPECT_TRUE(equal(mul(x, k(-2)), neg(mul(k(2), x))));
  EXPECT_TRUE(equal(mul(k(2), neg(x)), mul(k(-2), x)));
  EXPECT_TRUE(equal(div(x, k(-2)), neg(div(x, k(2)))));
  EXPECT_TRUE(equal(div(k(-2), x), neg(div(k(2), x))));
}

TEST(ExprIdentity, ConstantsToTheLeftOfProducts) {
  const Expr x = var(X), y = var(Y);
  const Expr e = mul(x, k(2));
  ASSERT_EQ(e->op, Op::Mul);
  EXPECT_TRUE(is_const(e->args[0]));
  EXPECT_TRUE(equal(e, mul(k(2), x)));
  EXPECT_TRUE(equal(mul(k(3), mul(k(2), x)), mul(k(6), x)));
  EXPECT_TRUE(equal(mul(mul(k(2), x), k(3)), mul(k(6), x)));
  EXPECT_TRUE(equal(mul(mul(x, k(2)), k(-3)), neg(mul(k(6), x))));
  EXPECT_TRUE(equal(mul(k(0.5), mul(k(2), x)), x));  // 0.5*2 = 1
  // no deeper algebra
  EXPECT_EQ(str(mul(mul(k(2), x), y)), "2*x*y");
  EXPECT_EQ(str(mul(x, mul(k(2), y))), "x*(2*y)");
  EXPECT_EQ(str(add(x, x)), "x + x");
  EXPECT_EQ(str(mul(x, x)), "x*x");
}

// ---- hashing and equality -------------------------------------------------------

Expr sample_tree() {
  const Expr x = var(X), t = time();
  return add(mul(param(P), fn(Fn::Sin, sub(x, t))),
             div(pow(x, k(2.5)), fn(Fn::Atan2, var(Y), add(x, k(0.1)))));
}

TEST(ExprHash, StructurallyEqualTreesBuiltSeparately) {
  const Expr e1 = sample_tree(), e2 = sample_tree();
  EXPECT_EQ(e1.get(), e2.get());  // hash-consed: one node per structure
  EXPECT_EQ(e1->hash, e2->hash);
  EXPECT_TRUE(equal(e1, e2));
  std::unordered_set<Expr, ExprHash, ExprEqual> set{e1, e2, var(X), var(X)};
  EXPECT_EQ(set.size(), 2u);
}

TEST(ExprHash, DifferentTreesDiffer) {
  const Expr x = var(X), y = var(Y);
  const std::vector<std::pair<Expr, Expr>> pairs = {
      {sub(x, y), sub(y, x)},
      {var(1), param(1)},
      {var(1), var(2)},
      {k(0.1 + 0.2), k(0.3)},
      {fn(Fn::Sin, x), fn(Fn::Cos, x)},
      {fn(Fn::Min, x, y), fn(Fn::Max, x, y)},
      {fn(Fn::Min, x, y), fn(Fn::Min, y, x)},
      {add(x, y), mul(x, y)},
      {der(x), x},
      {time(), var(0)},
      {k(1), k(-1)},
  };
  for (const auto& [a, b] : pairs) {
    EXPECT_FALSE(equal(a, b)) << str(a) << " vs " << str(b);
    EXPECT_NE(a->hash, b->hash) << str(a) << " vs " << str(b);
  }
}

// e_{k+1} = e_k*e_k + 1: a DAG of k levels whose tree has ~2^k nodes.
Expr deep_dag(int levels, const Expr& leaf) {
  Expr e = leaf;
  for (int i = 0; i < levels; ++i) e = add(mul(e, e), k(1));
  return e;
}

TEST(ExprHash, SharedDagsCompareInLinearTime) {
  const Expr a = deep_dag(80, var(X)), b = deep_dag(80, var(X));
  EXPECT_EQ(a.get(), b.get());  // hash-consed (raw DAGs below take the memoised path)
  EXPECT_TRUE(equal(a, b));
  EXPECT_FALSE(equal(a, deep_dag(80, var(Y))));
  // same DAG shape at the top, different only at one leaf deep down
  const Expr c = add(mul(a, b), k(1));
  const Expr d = add(mul(b, deep_dag(80, var(X))), k(1));
  EXPECT_TRUE(equal(c, d));
}

// Nodes built by hand keep hash 0: equal() must then decide on structure alone.
Expr raw_dag(int levels, const Expr& leaf) {
  Expr e = leaf;
  for (int i = 0; i < levels; ++i)
    e = raw(Op::Add, {raw(Op::Mul, {e, e}), raw(Op::Const, {}, 1.0)});
  return e;
}

TEST(ExprHash, EqualDoesNotTrustHashesAlone) {
  const auto rv = [](int id) { return raw(Op::Var, {}, 0.0, id); };
  const auto rp = [](int id) { return raw(Op::Param, {}, 0.0, id); };
  const auto rc = [](double v) { return raw(Op::Const, {}, v); };
  const auto rcall = [](Fn f, Expr a) { return raw(Op::Call, {std::move(a)}, 0.0, -1, f); };
  EXPECT_TRUE(equal(raw(Op::Add, {rv(1), rc(2)}), raw(Op::Add, {rv(1), rc(2)})));
  EXPECT_FALSE(equal(raw(Op::Add, {rv(1), rc(2)}), raw(Op::Add, {rv(2), rc(2)})));
  EXPECT_FALSE(equal(raw(Op::Add, {rv(1), rc(2)}), raw(Op::Add, {rv(1), rc(3)})));
  EXPECT_FALSE(equal(raw(Op::Add, {rv(1), rc(2)}), raw(Op::Sub, {rv(1), rc(2)})));
  EXPECT_FALSE(equal(raw(Op::Add, {rv(1), rc(2)}), raw(Op::Add, {rp(1), rc(2)})));
  EXPECT_FALSE(equal(rcall(Fn::Sin, rv(1)), rcall(Fn::Cos, rv(1))));
  EXPECT_FALSE(equal(raw(Op::Neg, {rv(1)}), raw(Op::Der, {rv(1)})));
  // large shared DAGs (past the plain recursion's budget): memoised path
  EXPECT_TRUE(equal(raw_dag(80, rv(1)), raw_dag(80, rv(1))));
  EXPECT_FALSE(equal(raw_dag(80, rv(1)), raw_dag(80, rv(2))));
  EXPECT_FALSE(equal(raw_dag(80, rv(1)), raw_dag(80, rp(1))));
  EXPECT_FALSE(equal(raw_dag(80, rc(1)), raw_dag(80, rc(-1))));
  EXPECT_FALSE(equal(raw_dag(80, rcall(Fn::Sin, rv(1))), raw_dag(80, rcall(Fn::Cos, rv(1)))));
  EXPECT_FALSE(equal(raw(Op::Add, {raw_dag(80, rv(1)), rc(1)}),
                     raw(Op::Sub, {raw_dag(80, rv(1)), rc(1)})));
  // a difference found only after the budget ran out
  EXPECT_FALSE(equal(raw(Op::Add, {raw_dag(80, rv(1)), raw(Op::Neg, {rv(1)})}),
                     raw(Op::Add, {raw_dag(80, rv(1)), raw(Op::Der, {rv(1)})})));
  EXPECT_FALSE(equal(raw(Op::Add, {raw_dag(80, rv(1)), raw(Op::Neg, {rv(1)})}),
                     raw(Op::Add, {raw_dag(80, rv(1)), raw(Op::Neg, {rv(2)})})));
  EXPECT_TRUE(equal(raw(Op::Add, {raw_dag(80, rv(1)), raw(Op::Neg, {rv(1)})}),
                    raw(Op::Add, {raw_dag(80, rv(1)), raw(Op::Neg, {rv(1)})})));
}

TEST(ExprHash, ConstructorsShareEqualNodes) {
  // A node outlives nothing: when the last reference goes, a new one is built.
  const Node* first = nullptr;
  {
    const Expr a = add(var(X), k(2));
    first = a.get();
    EXPECT_EQ(add(var(X), k(2)).get(), first);
  }
  const Expr again = add(var(X), k(2));
  EXPECT_TRUE(equal(again, add(var(X), k(2))));
  EXPECT_EQ(again.get(), add(var(X), k(2)).get());
  // -0.0 and 0.0, and every NaN, are one constant
  EXPECT_EQ(k(-0.0).get(), k(0.0).get());
  EXPECT_EQ(k(kNaN).get(), k(-kNaN).get());
  // a hand-built node is never handed out by the constructors
  const Expr r = raw(Op::Var, {}, 0.0, X);
  EXPECT_NE(var(X).get(), r.get());
}

TEST(ExprHash, TableKeepsFindingNodesAsOthersComeAndGo) {
  // Many nodes made and dropped in an interleaved order (the table moves
  // entries when one leaves): every live one is still the one handed out.
  for (int round = 0; round < 3; ++round) {
    std::vector<Expr> made;
    for (int i = 0; i < 20000; ++i) made.push_back(add(var(i % 97), k(i + round + 1)));
    for (std::size_t i = 0; i < made.size(); i += 2 + round) made[i].reset();
    for (int i = 0; i < 20000; ++i) {
      const Expr again = add(var(i % 97), k(i + round + 1));
      if (made[static_cast<std::size_t>(i)]) {
        EXPECT_EQ(again.get(), made[static_cast<std::size_t>(i)].get());
      }
      EXPECT_EQ(again->args[0]->id, i % 97);
    }
  }
}

TEST(ExprHash, NoCollisionsOnRandomTrees) {
  Random rnd(12345);
  std::unordered_map<std::size_t, std::string> by_hash;
  std::unordered_map<std::string, std::size_t> by_text;
  int distinct = 0;
  for (int i = 0; i < 3000; ++i) {
    const Expr e = smart(rnd.tree(5));
    const std::string s = str(e);
    auto [it, fresh] = by_text.emplace(s, e->hash);
    if (!fresh) {
      EXPECT_EQ(it->second, e->hash) << s;  // equal text => equal tree here => equal hash
      continue;
    }
    ++distinct;
    auto [jt, new_hash] = by_hash.emplace(e->hash, s);
    EXPECT_TRUE(new_hash) << "hash collision: " << s << " and " << jt->second;
  }
  EXPECT_GT(distinct, 1500);
}

// ---- inspection -------------------------------------------------------------------

TEST(ExprInspect, Collectors) {
  const Expr e = add(mul(param(P), var(X)), sub(der(var(Y)), div(param(Q), time())));
  std::unordered_set<int> vars, params;
  collect_vars(e, vars);
  collect_params(e, params);
  EXPECT_EQ(vars, (std::unordered_set<int>{X, Y}));
  EXPECT_EQ(params, (std::unordered_set<int>{P, Q}));
  EXPECT_TRUE(depends_on_time(e));
  EXPECT_FALSE(depends_on_time(mul(var(X), param(P))));
  EXPECT_TRUE(contains_der(e));
  EXPECT_FALSE(contains_der(sample_tree()));
  EXPECT_TRUE(contains_der(fn(Fn::Sin, add(k(1), der(var(X))))));
}

TEST(ExprInspect, Size) {
  EXPECT_EQ(size(var(X)), 1u);
  EXPECT_EQ(size(add(var(X), k(1))), 3u);
  EXPECT_EQ(size(fn(Fn::Atan2, var(X), neg(var(Y)))), 4u);
  // shared sub-trees count once per occurrence
  const Expr s = fn(Fn::Sin, var(X));
  EXPECT_EQ(size(mul(s, s)), 5u);
  EXPECT_EQ(size(mul(s, s)), size(mul(fn(Fn::Sin, var(X)), fn(Fn::Sin, var(X)))));
  // s_{k+1} = 2 s_k + 3, s_0 = 1  =>  s_k = 2^(k+2) - 3
  EXPECT_EQ(size(deep_dag(10, var(X))), (std::size_t{1} << 12) - 3);
  EXPECT_EQ(size(deep_dag(100, var(X))), std::numeric_limits<std::size_t>::max());
}

// ---- differentiation ---------------------------------------------------------------

TEST(ExprDiff, Basics) {
  const Expr x = var(X), y = var(Y);
  EXPECT_TRUE(is_one(diff_var(x, X)));
  EXPECT_TRUE(is_zero(diff_var(y, X)));
  EXPECT_TRUE(is_zero(diff_var(param(P), X)));
  EXPECT_TRUE(is_zero(diff_var(time(), X)));
  EXPECT_TRUE(is_zero(diff_var(k(3), X)));
  EXPECT_TRUE(is_zero(diff_var(der(x), X)));  // opaque
  EXPECT_TRUE(equal(diff_var(fn(Fn::Sin, x), X), fn(Fn::Cos, x)));
  EXPECT_TRUE(equal(diff_var(pow(x, k(3)), X), mul(k(3), pow(x, k(2)))));
  EXPECT_TRUE(equal(diff_var(pow(x, k(2)), X), mul(k(2), x)));
  EXPECT_TRUE(equal(diff_var(mul(param(P), x), X), param(P)));
  EXPECT_TRUE(equal(diff_var(fn(Fn::Abs, x), X), fn(Fn::Sign, x)));
  EXPECT_TRUE(is_zero(diff_var(fn(Fn::Sign, x), X)));
  EXPECT_TRUE(is_zero(diff_var(fn(Fn::Step, x), X)));
  // (a kink of min/max selects a side: select, not an event's heaviside)
  EXPECT_TRUE(equal(diff_var(fn(Fn::Min, x, y), X), fn(Fn::Select, sub(y, x))));
  EXPECT_TRUE(equal(diff_var(fn(Fn::Max, x, y), X), fn(Fn::Select, sub(x, y))));
  EXPECT_TRUE(equal(diff_var(fn(Fn::Min, x, y), Y), sub(k(1), fn(Fn::Select, sub(y, x)))));
  EXPECT_TRUE(is_zero(diff_var(fn(Fn::Select, x), X)));
  EXPECT_TRUE(is_zero(diff_var(fn(Fn::Frozen, x), X)));  // its value is x, its derivative 0
  EXPECT_TRUE(is_zero(diff_var(fn(Fn::Frozen, mul(x, x)), X)));
  EXPECT_TRUE(equal(diff_var(fn(Fn::Log, x), X), div(k(1), x)));
  EXPECT_TRUE(equal(diff_var(fn(Fn::Exp, mul(k(2), x)), X), mul(k(2), fn(Fn::Exp, mul(k(2), x)))));
  EXPECT_TRUE(equal(diff_var(div(x, param(P)), X), div(k(1), param(P))));
  EXPECT_EQ(str(diff_var(div(param(P), x), X)), "-p/x^2");
  EXPECT_EQ(str(diff_var(pow(x, param(P)), X)), "p*x^(p - 1)");
  EXPECT_EQ(str(diff_var(pow(k(2), x), X)), "0.6931471805599453*2^x");
}

// Inner arguments with known ranges at the sample points below:
// u = 0.3*x + 0.2*x*y + 0.05 is in (0.1, 0.6) for x in [0.3, 1.3], y in [0.1, 0.6].
Expr inner_u() {
  const Expr x = var(X), y = var(Y);
  return add(add(mul(k(0.3), x), mul(mul(k(0.2), x), y)), k(0.05));
}
Expr inner_v() { return sub(mul(var(X), fn(Fn::Cos, var(Y))), k(0.9)); }  // changes sign

std::vector<Env> sample_points() {
  std::vector<Env> pts;
  for (double x : {0.3, 0.75, 1.3})
    for (double y : {0.1, 0.45, 0.6}) {
      Env e;
      e.vars = {{X, x}, {Y, y}, {Z, 0.25}};
      e.params = {{P, 2.5}, {Q, -0.5}};
      e.t = 0.4;
      pts.push_back(e);
    }
  return pts;
}

TEST(ExprDiff, EveryFunctionAgainstFiniteDifferences) {
  for (int f = 0; f <= static_cast<int>(Fn::Step); ++f) {
    const Fn ff = static_cast<Fn>(f);
    std::vector<Expr> args{inner_u()};
    if (arity(ff) == 2) args.push_back(inner_v());
    const Expr e = call(ff, args);
    for (int id : {X, Y}) {
      const Expr de = diff_var(e, id);
      for (const Env& env : sample_points()) {
        if ((ff == Fn::Min || ff == Fn::Max) &&
            std::fabs(eval(args[0], env) - eval(args[1], env)) < 1e-3)
          continue;  // at the kink
        EXPECT_TRUE(derivative_matches(e, de, env, id)) << fn_name(ff);
      }
    }
  }
  // the nonsmooth ones also where their argument is negative
  for (Fn ff : {Fn::Abs, Fn::Sign, Fn::Step, Fn::Select}) {
    const Expr e = call(ff, {inner_v()});
    const Expr de = diff_var(e, X);
    Env env = sample_points()[0];
    ASSERT_LT(eval(inner_v(), env), 0);
    EXPECT_TRUE(derivative_matches(e, de, env, X)) << fn_name(ff);
  }
}

TEST(ExprDiff, OperatorsAgainstFiniteDifferences) {
  const Expr x = var(X), y = var(Y), u = inner_u(), v = inner_v();
  const std::vector<Expr> cases = {
      neg(mul(u, v)),
      add(u, mul(y, v)),
      sub(mul(x, u), v),
      mul(u, v),
      div(u, v),
      div(u, param(P)),
      div(param(P), u),
      pow(u, k(3)),
      pow(u, k(-1.5)),
      pow(u, param(P)),
      pow(u, v),
      pow(k(2), v),
      pow(param(P), mul(x, y)),
      fn(Fn::Sin, fn(Fn::Exp, mul(u, v))),
      mul(fn(Fn::Sqrt, u), fn(Fn::Atan2, v, u)),
      add(der(x), mul(x, x)),  // der is opaque: treated as a constant
  };
  for (const Expr& e : cases)
    for (int id : {X, Y}) {
      const Expr de = diff_var(e, id);
      for (const Env& env : sample_points()) {
        if (contains_der(e)) {
          // d/dx (der(x) + x*x) = 2x by the opaque rule
          EXPECT_TRUE(equal(de, id == X ? add(x, x) : k(0))) << str(de);
          continue;
        }
        EXPECT_TRUE(derivative_matches(e, de, env, id));
      }
    }
}

TEST(ExprDiff, Time) {
  const Expr x = var(X), t = time();
  const Expr e = add(mul(fn(Fn::Sin, t), x), pow(t, k(2)));
  const Expr de = diff_time(e);
  EXPECT_EQ(str(de), "cos(t)*x + 2*t");
  EXPECT_TRUE(is_zero(diff_time(x)));
  EXPECT_TRUE(is_zero(diff_time(der(mul(t, x)))));
  EXPECT_TRUE(is_one(diff_time(t)));
  const Expr e2 = mul(fn(Fn::Step, sub(t, k(1))), fn(Fn::Exp, mul(neg(t), param(P))));
  for (const Env& env : sample_points()) {
    EXPECT_TRUE(derivative_matches(e, de, env, -1));
    EXPECT_TRUE(derivative_matches(e2, diff_time(e2), env, -1));
  }
}

// The constructors summarise each sub-tree (variables, t, der, parameters);
// walks skip the parts a summary rules out, and must give what a full walk gives.
TEST(ExprSummary, WalksThatSkipGiveTheFullWalksAnswer) {
  const Expr x = var(X), y = var(Y), t = time();
  const Expr e = add(mul(param(P), fn(Fn::Sin, t)), mul(x, der(y)));
  EXPECT_TRUE(depends_on_time(e));
  EXPECT_TRUE(contains_der(e));
  EXPECT_FALSE(depends_on_time(mul(x, der(y))));
  EXPECT_FALSE(contains_der(mul(param(P), fn(Fn::Sin, t))));
  std::unordered_set<int> vars, params;
  collect_vars(e, vars);
  collect_params(e, params);
  EXPECT_EQ(vars, (std::unordered_set<int>{X, Y}));
  EXPECT_EQ(params, (std::unordered_set<int>{P}));
  // ids 64 apart share a summary bit: still told apart
  EXPECT_TRUE(is_zero(diff_var(var(X + 64), X)));
  EXPECT_TRUE(is_one(diff_var(add(var(X + 64), x), X)));
  EXPECT_TRUE(equal(substitute(add(var(X + 64), x), {{X, y}}), add(var(X + 64), y)));
  // what differentiating a sub-tree without the variable gives is not always
  // 0: 0*inf and 0/0 stay what they were
  EXPECT_EQ(str(diff_var(mul(k(kInf), y), X)), "nan");
  EXPECT_EQ(str(diff_var(div(y, k(0)), X)), "0/0");
  EXPECT_EQ(str(diff_time(div(y, k(0)))), "0/0");
  EXPECT_TRUE(is_zero(diff_var(mul(param(P), y), X)));
  // the variable tests, alternating with collect_vars (their walks share marks)
  const Expr w = add(mul(x, var(X + 64)), der(y));
  for (int i = 0; i < 3; ++i) {
    std::unordered_set<int> all;
    collect_vars(w, all);
    EXPECT_EQ(all.size(), 3u);
    EXPECT_TRUE(mentions_var(w, Y));
    EXPECT_FALSE(mentions_var(w, Z));
    EXPECT_FALSE(mentions_var(w, Z + 64));
    EXPECT_FALSE(mentions_only_var(w, X));
    EXPECT_FALSE(mentions_only_var(mul(x, var(X + 64)), X));
    EXPECT_TRUE(mentions_only_var(mul(x, fn(Fn::Sin, x)), X));
    EXPECT_TRUE(mentions_only_var(mul(param(P), t), X));
  }
  // hand-built trees carry no summary: walked in full
  const Expr r = raw(Op::Add, {raw(Op::Var, {}, 0.0, X), raw(Op::Der, {raw(Op::Time, {})})});
  EXPECT_TRUE(contains_der(r));
  EXPECT_TRUE(depends_on_time(r));
  EXPECT_TRUE(is_one(diff_var(r, X)));
  std::unordered_set<int> raw_vars;
  collect_vars(r, raw_vars);
  EXPECT_EQ(raw_vars, (std::unordered_set<int>{X}));
}

TEST(ExprDiff, SharedDagStaysLinear) {
  const Expr e = deep_dag(60, var(X));
  const Expr de = diff_var(e, X);  // would never finish without the memo
  EXPECT_FALSE(is_zero(de));
  // and it is right, checked numerically on a small one
  const Expr small = deep_dag(3, var(X));
  Env env;
  env.vars[X] = 0.3;
  EXPECT_TRUE(derivative_matches(small, diff_var(small, X), env, X));
}

// ---- substitution and rewriting -------------------------------------------------------

TEST(ExprSubstitute, ReplacesAndResimplifies) {
  const Expr x = var(X), y = var(Y), z = var(Z);
  EXPECT_TRUE(equal(substitute(add(x, y), {{X, mul(k(2), z)}}), add(mul(k(2), z), y)));
  EXPECT_TRUE(is_zero(substitute(sub(x, y), {{X, y}})));
  EXPECT_TRUE(is_zero(substitute(mul(x, y), {{Y, k(0)}})));
  double v = 0;
  ASSERT_TRUE(is_const(substitute(fn(Fn::Sin, x), {{X, k(0.5)}}), &v));
  EXPECT_EQ(v, std::sin(0.5));
  // simultaneous, not sequential
  EXPECT_TRUE(equal(substitute(sub(x, y), {{X, y}, {Y, x}}), sub(y, x)));
  // inside der too, through the der() constructor
  EXPECT_TRUE(is_one(substitute(der(x), {{X, time()}})));
  EXPECT_TRUE(equal(substitute(der(x), {{X, y}}), der(y)));
  // untouched trees come back as the same node
  const Expr e = sample_tree();
  EXPECT_EQ(substitute(e, {{Z, k(1)}}), e);
  EXPECT_EQ(substitute(e, {}), e);
}

TEST(ExprSubstitute, SharedDagStaysLinear) {
  const Expr e = deep_dag(80, var(X));
  const Expr r = substitute(e, {{X, var(Y)}});  // would never finish without the memo
  EXPECT_TRUE(equal(r, deep_dag(80, var(Y))));
  EXPECT_TRUE(is_const(substitute(deep_dag(5, var(X)), {{X, k(0)}})));
}

TEST(ExprRewrite, TopDownAndReplacementsNotRevisited) {
  const Expr x = var(X), y = var(Y);
  // replace der(v) by a fresh var 10+v
  const Expr e = add(mul(param(P), der(x)), der(y));
  const Expr r = rewrite(e, [](const Expr& n) -> Expr {
    if (n->op == Op::Der && n->args[0]->op == Op::Var) return var(10 + n->args[0]->id);
    return nullptr;
  });
  EXPECT_FALSE(contains_der(r));
  EXPECT_TRUE(equal(r, add(mul(param(P), var(10 + X)), var(10 + Y))));
  // the replacement x+1 is not visited again (no x+1+1)
  const Expr r2 = rewrite(mul(x, y), [](const Expr& n) -> Expr {
    return n->op == Op::Var && n->id == X ? add(n, k(1)) : nullptr;
  });
  EXPECT_EQ(str(r2), "(x + 1)*y");
  // parents are seen before children, and results are re-simplified
  std::vector<Op> order;
  const Expr r3 = rewrite(mul(x, fn(Fn::Sin, y)), [&](const Expr& n) -> Expr {
    order.push_back(n->op);
    return n->op == Op::Call ? k(1) : nullptr;
  });
  EXPECT_EQ(r3, x);
  EXPECT_EQ(order, (std::vector<Op>{Op::Mul, Op::Var, Op::Call}));
}

// ---- affine decomposition ----------------------------------------------------------

TEST(ExprAffine, AffineCases) {
  const Expr x = var(X), y = var(Y), z = var(Z), t = time();
  std::vector<Expr> coeff;
  Expr rest;
  const Expr e = add(add(mul(k(2), x), mul(mul(k(3), y), z)), fn(Fn::Sin, t));
  ASSERT_TRUE(affine_in(e, {X, Y}, coeff, rest));
  ASSERT_EQ(coeff.size(), 2u);
  EXPECT_TRUE(equal(coeff[0], k(2))) << str(coeff[0]);
  EXPECT_TRUE(equal(coeff[1], mul(k(3), z))) << str(coeff[1]);
  EXPECT_TRUE(equal(rest, fn(Fn::Sin, t))) << str(rest);

  const Expr e2 = add(sub(div(x, param(P)), mul(param(Q), y)), k(4));
  ASSERT_TRUE(affine_in(e2, {X, Y, Z}, coeff, rest));
  ASSERT_EQ(coeff.size(), 3u);
  EXPECT_TRUE(equal(coeff[0], div(k(1), param(P)))) << str(coeff[0]);
  EXPECT_TRUE(equal(coeff[1], neg(param(Q)))) << str(coeff[1]);
  EXPECT_TRUE(is_zero(coeff[2]));
  EXPECT_TRUE(equal(rest, k(4))) << str(rest);

  // nonlinear in the others is fine; der of a non-unknown is fine
  const Expr e3 = add(mul(fn(Fn::Exp, z), sub(x, fn(Fn::Abs, z))), der(z));
  ASSERT_TRUE(affine_in(e3, {X}, coeff, rest));
  EXPECT_TRUE(equal(coeff[0], fn(Fn::Exp, z)));
  EXPECT_EQ(str(rest), "-exp(z)*abs(z) + der(z)");
  // the decomposition reproduces e numerically
  for (const Env& env : sample_points()) {
    ASSERT_TRUE(affine_in(e, {X, Y}, coeff, rest));
    const double sum = eval(coeff[0], env) * env.vars.at(X) + eval(coeff[1], env) * env.vars.at(Y) +
                       eval(rest, env);
    EXPECT_NEAR(sum, eval(e, env), 1e-12);
  }
}

TEST(ExprAffine, NonAffineCases) {
  const Expr x = var(X), y = var(Y);
  const std::vector<std::pair<Expr, std::vector<int>>> cases = {
      {mul(x, y), {X, Y}},
      {fn(Fn::Sin, x), {X}},
      {pow(x, k(2)), {X}},
      {div(k(1), x), {X}},
      {div(x, y), {Y}},
      {pow(k(2), x), {X}},
      {fn(Fn::Abs, x), {X}},
      {fn(Fn::Step, sub(x, k(1))), {X}},
      {mul(y, fn(Fn::Sign, x)), {X}},
      {fn(Fn::Min, x, k(1)), {X}},
      {add(der(x), x), {X}},
      {add(der(mul(x, y)), y), {Y}},
  };
  for (const auto& [e, unknowns] : cases) {
    std::vector<Expr> coeff{k(42)};
    Expr rest = k(43);
    EXPECT_FALSE(affine_in(e, unknowns, coeff, rest)) << str(e);
    // outputs untouched
    ASSERT_EQ(coeff.size(), 1u);
    EXPECT_TRUE(equal(coeff[0], k(42)));
    EXPECT_TRUE(equal(rest, k(43)));
  }
  // a Step of something else is fine
  std::vector<Expr> coeff;
  Expr rest;
  EXPECT_TRUE(affine_in(mul(fn(Fn::Step, y), x), {X}, coeff, rest));
  EXPECT_TRUE(equal(coeff[0], fn(Fn::Step, y)));
  EXPECT_TRUE(is_zero(rest));
}

// ---- to_string -----------------------------------------------------------------------

TEST(ExprToString, Precedence) {
  const Expr a = var(A), b = var(B), c = var(C), x = var(X), y = var(Y);
  EXPECT_EQ(str(sub(a, sub(b, c))), "a - (b - c)");
  EXPECT_EQ(str(sub(sub(a, b), c)), "a - b - c");
  EXPECT_EQ(str(add(sub(a, b), c)), "a - b + c");
  EXPECT_EQ(str(sub(a, add(b, c))), "a - (b + c)");
  EXPECT_EQ(str(add(a, add(b, c))), "a + (b + c)");
  EXPECT_EQ(str(add(add(a, b), c)), "a + b + c");
  EXPECT_EQ(str(mul(a, add(b, c))), "a*(b + c)");
  EXPECT_EQ(str(mul(add(a, b), c)), "(a + b)*c");
  EXPECT_EQ(str(div(a, mul(b, c))), "a/(b*c)");
  EXPECT_EQ(str(mul(div(a, b), c)), "a/b*c");
  EXPECT_EQ(str(div(div(a, b), c)), "a/b/c");
  EXPECT_EQ(str(div(a, div(b, c))), "a/(b/c)");
  EXPECT_EQ(str(sub(a, mul(b, c))), "a - b*c");
  EXPECT_EQ(str(add(mul(a, b), div(b, c))), "a*b + b/c");
  EXPECT_EQ(str(neg(pow(x, k(2)))), "-x^2");
  EXPECT_EQ(str(pow(neg(x), k(2))), "(-x)^2");
  EXPECT_EQ(str(neg(mul(a, b))), "-a*b");
  EXPECT_EQ(str(mul(neg(a), b)), "-a*b");
  EXPECT_EQ(str(div(neg(a), b)), "-a/b");
  EXPECT_EQ(str(mul(a, neg(mul(b, c)))), "-a*(b*c)");
  EXPECT_EQ(str(neg(add(a, b))), "-(a + b)");
  EXPECT_EQ(str(add(neg(a), b)), "-a + b");
  EXPECT_EQ(str(sub(neg(a), b)), "-a - b");
  EXPECT_EQ(str(pow(a, pow(b, c))), "a^b^c");
  EXPECT_EQ(str(pow(pow(a, b), c)), "(a^b)^c");
  EXPECT_EQ(str(pow(mul(a, b), k(2))), "(a*b)^2");
  EXPECT_EQ(str(pow(a, mul(b, c))), "a^(b*c)");
  EXPECT_EQ(str(mul(pow(a, b), c)), "a^b*c");
  EXPECT_EQ(str(pow(x, k(-1))), "x^(-1)");
  EXPECT_EQ(str(pow(x, neg(y))), "x^(-y)");
  EXPECT_EQ(str(pow(k(-2), x)), "(-2)^x");
  EXPECT_EQ(str(mul(k(2), pow(x, k(2)))), "2*x^2");
  EXPECT_EQ(str(mul(x, k(2))), "2*x");
  EXPECT_EQ(str(mul(x, k(-2))), "-2*x");
  EXPECT_EQ(str(add(a, k(-2))), "a - 2");
  EXPECT_EQ(str(sub(a, k(-2))), "a + 2");
  EXPECT_EQ(str(sub(a, neg(mul(b, c)))), "a + b*c");
  EXPECT_EQ(str(add(a, neg(mul(b, c)))), "a - b*c");
  EXPECT_EQ(str(sub(k(1), fn(Fn::Step, sub(b, a)))), "1 - heaviside(b - a)");
}

TEST(ExprToString, NonCanonicalTreesStillParenthesiseSafely) {
  const Expr a = var(A), b = var(B);
  EXPECT_EQ(str(raw(Op::Neg, {raw(Op::Neg, {a})})), "-(-a)");
  EXPECT_EQ(str(raw(Op::Neg, {k(-2)})), "-(-2)");
  EXPECT_EQ(str(raw(Op::Add, {a, raw(Op::Neg, {b})})), "a + (-b)");
  EXPECT_EQ(str(raw(Op::Sub, {a, k(-2)})), "a - (-2)");
  EXPECT_EQ(str(raw(Op::Mul, {a, k(-2)})), "a*(-2)");
  EXPECT_EQ(str(raw(Op::Mul, {k(-2), a})), "-2*a");
  EXPECT_EQ(str(raw(Op::Neg, {raw(Op::Mul, {raw(Op::Neg, {a}), b})})), "-(-a*b)");
  EXPECT_EQ(str(raw(Op::Pow, {raw(Op::Neg, {raw(Op::Mul, {a, b})}), k(2)})), "(-a*b)^2");
}

TEST(ExprToString, LeavesConstantsCalls) {
  EXPECT_EQ(str(k(0.4)), "0.4");
  EXPECT_EQ(str(k(1e-06)), "1e-06");
  EXPECT_EQ(str(k(60)), "60");
  EXPECT_EQ(str(k(-2.5)), "-2.5");
  EXPECT_EQ(str(k(1e20)), "1e+20");
  EXPECT_EQ(str(k(0.1 + 0.2)), "0.30000000000000004");
  EXPECT_EQ(str(k(kInf)), "inf");
  EXPECT_EQ(str(k(-kInf)), "-inf");
  EXPECT_EQ(str(k(kNaN)), "nan");
  EXPECT_EQ(str(neg(mul(k(kNaN), var(X)))), "-(nan*x)");  // "-nan*x" would read back as nan*x
  EXPECT_EQ(str(var(X)), "x");
  EXPECT_EQ(str(param(Q)), "q");
  EXPECT_EQ(str(time()), "t");
  EXPECT_EQ(str(fn(Fn::Sin, var(X))), "sin(x)");
  EXPECT_EQ(str(fn(Fn::Atan2, var(Y), var(X))), "atan2(y, x)");
  EXPECT_EQ(str(fn(Fn::Min, var(A), neg(var(B)))), "min(a, -b)");
  EXPECT_EQ(str(fn(Fn::Step, sub(time(), k(2)))), "heaviside(t - 2)");
  EXPECT_EQ(str(der(var(X))), "der(x)");
  EXPECT_EQ(str(neg(der(var(X)))), "-der(x)");
  Namer custom;
  custom.time = "time";
  EXPECT_EQ(to_string(add(var(3), mul(param(0), time())), custom), "v3 + p0*time");
}

// ---- to_cpp -------------------------------------------------------------------------

TEST(ExprToCpp, Constants) {
  EXPECT_EQ(cpp(k(60)), "60.0");
  EXPECT_EQ(cpp(k(0)), "0.0");
  EXPECT_EQ(cpp(k(0.4)), "0.4");
  EXPECT_EQ(cpp(k(1e-06)), "1e-06");
  EXPECT_EQ(cpp(k(1e20)), "1e+20");
  EXPECT_EQ(cpp(k(-2)), "-2.0");
  EXPECT_EQ(cpp(k(kInf)), "std::numeric_limits<double>::infinity()");
  EXPECT_EQ(cpp(k(-kInf)), "-std::numeric_limits<double>::infinity()");
  EXPECT_EQ(cpp(k(kNaN)), "std::numeric_limits<double>::quiet_NaN()");
  EXPECT_EQ(cpp(mul(var(A), k(kInf))), "std::numeric_limits<double>::infinity() * a");
  EXPECT_EQ(cpp(sub(var(A), k(-kInf))), "a + std::numeric_limits<double>::infinity()");
}

TEST(ExprToCpp, Operators) {
  const Expr a = var(A), b = var(B), c = var(C), x = var(X), y = var(Y);
  EXPECT_EQ(cpp(mul(a, k(-2))), "-2.0 * a");
  EXPECT_EQ(cpp(sub(a, mul(b, c))), "a - b * c");
  EXPECT_EQ(cpp(div(a, mul(b, c))), "a / (b * c)");
  EXPECT_EQ(cpp(sub(a, sub(b, c))), "a - (b - c)");
  EXPECT_EQ(cpp(mul(mul(k(2), x), y)), "2.0 * x * y");
  EXPECT_EQ(cpp(mul(x, mul(y, c))), "x * (y * c)");
  EXPECT_EQ(cpp(neg(add(a, b))), "-(a + b)");
  EXPECT_EQ(cpp(div(x, k(0))), "x / 0.0");
  EXPECT_EQ(cpp(raw(Op::Mul, {a, k(-2)})), "a * (-2.0)");
  EXPECT_EQ(cpp(raw(Op::Sub, {a, raw(Op::Neg, {b})})), "a - (-b)");
  EXPECT_EQ(cpp(add(mul(param(P), var(X)), time())), "p * x + t");
}

TEST(ExprToCpp, PowersAndCalls) {
  const Expr a = var(A), b = var(B), x = var(X), y = var(Y);
  EXPECT_EQ(cpp(pow(x, k(2))), "(x*x)");
  EXPECT_EQ(cpp(pow(x, k(3))), "(x*x*x)");
  EXPECT_EQ(cpp(pow(param(P), k(2))), "(p*p)");
  EXPECT_EQ(cpp(pow(time(), k(2))), "(t*t)");
  EXPECT_EQ(cpp(neg(pow(x, k(2)))), "-(x*x)");
  EXPECT_EQ(cpp(mul(a, pow(x, k(2)))), "a * (x*x)");
  EXPECT_EQ(cpp(pow(x, k(4))), "std::pow(x, 4.0)");
  EXPECT_EQ(cpp(pow(x, k(0.5))), "std::pow(x, 0.5)");
  EXPECT_EQ(cpp(pow(x, k(-1))), "std::pow(x, -1.0)");
  EXPECT_EQ(cpp(pow(x, y)), "std::pow(x, y)");
  EXPECT_EQ(cpp(pow(fn(Fn::Sin, x), k(2))), "std::pow(std::sin(x), 2.0)");
  EXPECT_EQ(cpp(pow(add(x, y), k(3))), "std::pow(x + y, 3.0)");
  EXPECT_EQ(cpp(fn(Fn::Step, sub(time(), k(2)))), "((t - 2.0) >= 0.0 ? 1.0 : 0.0)");
  EXPECT_EQ(cpp(fn(Fn::Sign, x)), "((x) > 0.0 ? 1.0 : ((x) < 0.0 ? -1.0 : 0.0))");
  EXPECT_EQ(cpp(fn(Fn::Abs, x)), "std::fabs(x)");
  EXPECT_EQ(cpp(fn(Fn::Min, a, b)), "std::fmin(a, b)");
  EXPECT_EQ(cpp(fn(Fn::Max, a, neg(b))), "std::fmax(a, -b)");
  EXPECT_EQ(cpp(fn(Fn::Atan2, y, x)), "std::atan2(y, x)");
  const std::pair<Fn, const char*> plain[] = {
      {Fn::Sin, "sin"},   {Fn::Cos, "cos"},   {Fn::Tan, "tan"},   {Fn::Asin, "asin"},
      {Fn::Acos, "acos"}, {Fn::Atan, "atan"}, {Fn::Sinh, "sinh"}, {Fn::Cosh, "cosh"},
      {Fn::Tanh, "tanh"}, {Fn::Exp, "exp"},   {Fn::Log, "log"},   {Fn::Sqrt, "sqrt"}};
  for (const auto& [f, name] : plain)
    EXPECT_EQ(cpp(fn(f, x)), std::string("std::") + name + "(x)");
  EXPECT_EQ(cpp(mul(k(2), fn(Fn::Step, x))), "2.0 * ((x) >= 0.0 ? 1.0 : 0.0)");
}

// ---- operations counted by the C++ printer (mbgc --stats) ---------------------------------

CppOps ops_of(const Expr& e) {
  CppOps ops;
  to_cpp(e, names(), &ops);
  return ops;
}

CppOps make_ops(std::size_t add, std::size_t mul, std::size_t div, std::size_t neg, std::size_t call,
                std::size_t compare) {
  CppOps o;
  o.add = add, o.mul = mul, o.div = div, o.neg = neg, o.call = call, o.compare = compare;
  return o;
}

std::string describe(const CppOps& o) {
  return "add " + std::to_string(o.add) + " mul " + std::to_string(o.mul) + " div " + std::to_string(o.div) +
         " neg " + std::to_string(o.neg) + " call " + std::to_string(o.call) + " compare " +
         std::to_string(o.compare);
}

TEST(ExprToCppOps, CountsWhatIsWritten) {
  const Expr a = var(A), b = var(B), x = var(X), y = var(Y);
  // x' = -k x + a sin(t), k = p, a = q, as written: "-p * x + q * std::sin(t)"
  // is a negation, two muls, an add and a call
  const Expr rhs = add(neg(mul(param(P), x)), mul(param(Q), fn(Fn::Sin, time())));
  EXPECT_EQ(cpp(rhs), "-p * x + q * std::sin(t)");
  EXPECT_EQ(ops_of(rhs), make_ops(1, 2, 0, 1, 1, 0)) << describe(ops_of(rhs));
  EXPECT_EQ(ops_of(rhs).total(), 5u);
  // the same as a sin(t) - k x: the negation is gone, 4 operations
  const Expr rhs2 = sub(mul(param(Q), fn(Fn::Sin, time())), mul(param(P), x));
  EXPECT_EQ(cpp(rhs2), "q * std::sin(t) - p * x");
  EXPECT_EQ(ops_of(rhs2), make_ops(1, 2, 0, 0, 1, 0)) << describe(ops_of(rhs2));
  EXPECT_EQ(ops_of(rhs2).total(), 4u);
  // leaves cost nothing
  EXPECT_EQ(ops_of(x).total(), 0u);
  EXPECT_EQ(ops_of(k(-2)).total(), 0u);
  EXPECT_EQ(ops_of(k(-kInf)).total(), 0u);
  // a unary minus counts, but not the sign of a literal: -2.0 * a is (-2.0) * a
  EXPECT_EQ(ops_of(neg(x)), make_ops(0, 0, 0, 1, 0, 0));
  EXPECT_EQ(cpp(mul(a, k(-2))), "-2.0 * a");
  EXPECT_EQ(ops_of(mul(a, k(-2))), make_ops(0, 1, 0, 0, 0, 0));
  EXPECT_EQ(ops_of(neg(div(k(2), mul(a, b)))), make_ops(0, 1, 1, 0, 0, 0));  // -2.0 / (a * b)
  EXPECT_EQ(ops_of(neg(mul(a, b))), make_ops(0, 1, 0, 1, 0, 0));              // -a * b
  EXPECT_EQ(ops_of(neg(add(a, b))), make_ops(1, 0, 0, 1, 0, 0));              // -(a + b)
  EXPECT_EQ(ops_of(sub(a, div(b, x))), make_ops(1, 0, 1, 0, 0, 0));
  // x^2 and x^3 of a leaf are written as products; other powers call std::pow
  EXPECT_EQ(ops_of(pow(x, k(2))), make_ops(0, 1, 0, 0, 0, 0));
  EXPECT_EQ(ops_of(pow(x, k(3))), make_ops(0, 2, 0, 0, 0, 0));
  EXPECT_EQ(ops_of(neg(pow(x, k(2)))), make_ops(0, 1, 0, 1, 0, 0));  // -(x*x)
  EXPECT_EQ(ops_of(pow(x, k(0.5))), make_ops(0, 0, 0, 0, 1, 0));
  EXPECT_EQ(ops_of(pow(add(x, y), k(2))), make_ops(1, 0, 0, 0, 1, 0));  // std::pow(x + y, 2.0)
  // calls, fabs/fmin/fmax included; step compares once; sign compares twice
  // and writes its argument twice, so the argument's work counts twice
  EXPECT_EQ(ops_of(fn(Fn::Atan2, y, mul(a, x))), make_ops(0, 1, 0, 0, 1, 0));
  EXPECT_EQ(ops_of(fn(Fn::Abs, x)), make_ops(0, 0, 0, 0, 1, 0));
  EXPECT_EQ(ops_of(fn(Fn::Min, a, neg(b))), make_ops(0, 0, 0, 1, 1, 0));
  EXPECT_EQ(ops_of(fn(Fn::Step, sub(time(), k(2)))), make_ops(1, 0, 0, 0, 0, 1));
  EXPECT_EQ(ops_of(fn(Fn::Sign, add(x, y))), make_ops(2, 0, 0, 0, 0, 2));
  EXPECT_EQ(ops_of(mul(a, fn(Fn::Sign, fn(Fn::Sin, x)))), make_ops(0, 1, 0, 0, 2, 2));
}

TEST(ExprToCppOps, AccumulatesAndLeavesTheTextAlone) {
  const Expr e = add(mul(var(A), fn(Fn::Cos, var(X))), div(var(B), param(P)));
  CppOps ops;
  const std::string once = to_cpp(e, names(), &ops);
  EXPECT_EQ(once, cpp(e));
  EXPECT_EQ(ops, make_ops(1, 1, 1, 0, 1, 0));
  to_cpp(e, names(), &ops);
  EXPECT_EQ(ops, make_ops(2, 2, 2, 0, 2, 0));
  EXPECT_EQ(ops.total(), 8u);
}

TEST(ExprToCpp, DerDoesNotCompile) {
  const std::string s = cpp(add(var(X), der(var(Y))));
  EXPECT_NE(s.find("MBGC_DER_NOT_REMOVED(y)"), std::string::npos) << s;
}

// ---- property tests on random trees ----------------------------------------------------

// The printed C++ must never contain what would not be a double literal or could
// mis-tokenize.
void check_cpp_text(const std::string& s) {
  int depth = 0;
  for (char ch : s) {
    depth += ch == '(' ? 1 : ch == ')' ? -1 : 0;
    ASSERT_GE(depth, 0) << s;
  }
  EXPECT_EQ(depth, 0) << s;
  for (const char* bad : {"- -", "+ -", "* -", "/ -", "--", "inf)", "inf ", "nan", "^"})
    EXPECT_EQ(s.find(bad), std::string::npos) << "'" << bad << "' in " << s;
  if (s.size() >= 3) {
    EXPECT_NE(s.substr(s.size() - 3), "inf") << s;
  }
  // every number has a '.' or an exponent
  for (std::size_t i = 0; i < s.size(); ++i) {
    const bool starts = std::isdigit(static_cast<unsigned char>(s[i])) &&
                        (i == 0 || !(std::isalnum(static_cast<unsigned char>(s[i - 1])) ||
                                     s[i - 1] == '_' || s[i - 1] == '.'));
    if (!starts) continue;
    std::size_t j = i;
    while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '.' ||
                            ((s[j] == '+' || s[j] == '-') && (s[j - 1] == 'e'))))
      ++j;
    const std::string num = s.substr(i, j - i);
    EXPECT_NE(num.find_first_of(".e"), std::string::npos) << num << " in " << s;
    i = j;
  }
}

TEST(ExprProperty, SimplificationPreservesValues) {
  Random rnd(20240601);
  int checked = 0, mismatches = 0;
  for (int i = 0; i < 3000; ++i) {
    const Expr r = rnd.tree(5);
    const Expr s = smart(r);
    for (int j = 0; j < 3; ++j) {
      const Env env = rnd.env();
      bool degenerate = false;
      const double vr = eval(r, env, &degenerate);
      if (degenerate) continue;  // x*0, a-a, 0/a, -0.0 = 0.0 ... differ here on purpose
      ++checked;
      const double vs = eval(s, env);
      if (!same_value(vr, vs, 1e-9)) {
        ++mismatches;
        ADD_FAILURE() << str(r) << "  ~>  " << str(s) << ": " << vr << " vs " << vs;
      }
    }
  }
  EXPECT_GT(checked, 3000);
  EXPECT_EQ(mismatches, 0);
}

TEST(ExprProperty, ToStringRoundTrips) {
  Random rnd(777);
  for (int i = 0; i < 3000; ++i) {
    const Expr s = smart(rnd.tree(6));
    const std::string text = str(s);
    Expr back;
    ASSERT_NO_THROW(back = parse(text)) << text;
    EXPECT_TRUE(equal(back, s)) << text << "  reparsed as  " << str(back);
    EXPECT_EQ(str(back), text);
  }
}

TEST(ExprProperty, ToStringOfRawTreesMeansTheTree) {
  // Non-canonical trees (Neg of Const, Neg of Neg, negative constants anywhere)
  // must still print to text that evaluates like the tree.
  Random rnd(4242);
  int checked = 0;
  for (int i = 0; i < 3000; ++i) {
    const Expr r = rnd.tree(5);
    const std::string text = str(r);
    Expr back;
    ASSERT_NO_THROW(back = parse(text)) << text;
    const Env env = rnd.env();
    bool degenerate = false;
    const double vr = eval(r, env, &degenerate);
    if (degenerate) continue;
    ++checked;
    EXPECT_TRUE(same_value(vr, eval(back, env), 1e-9)) << text;
  }
  EXPECT_GT(checked, 1500);
}

TEST(ExprProperty, ToCppText) {
  Random rnd(99);
  for (int i = 0; i < 2000; ++i) {
    const Expr r = rnd.tree(5);
    check_cpp_text(cpp(r));
    check_cpp_text(cpp(smart(r)));
  }
}

TEST(ExprProperty, CppOpsMatchTheText) {
  Random rnd(2718);
  std::size_t seen = 0;
  for (int i = 0; i < 3000; ++i) {
    const Expr e = smart(rnd.tree(6));
    CppOps ops;
    const std::string text = to_cpp(e, names(), &ops);
    EXPECT_EQ(ops, mbgc_test::cpp_ops_in_text(text)) << text << "\n  counted: " << describe(ops)
                                      << "\n  in text: " << describe(mbgc_test::cpp_ops_in_text(text));
    seen += ops.total();
  }
  EXPECT_GT(seen, 10000u);  // the trees do have operations
}

TEST(ExprProperty, HashAndEqualityAreStructural) {
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    Random r1(seed), r2(seed);
    const Expr a = smart(r1.tree(5)), b = smart(r2.tree(5));
    EXPECT_EQ(a->hash, b->hash);
    EXPECT_TRUE(equal(a, b)) << str(a);
    EXPECT_EQ(a.get(), b.get());  // hash-consed
  }
}

TEST(ExprProperty, DerivativesMatchFiniteDifferences) {
  Random rnd(31337);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const Expr e = smart(rnd.tree(4, /*smooth=*/true));
    const Expr da = diff_var(e, A), dt = diff_time(e);
    for (int j = 0; j < 2; ++j) {
      const Env env = rnd.env();
      for (int id : {int{A}, -1}) {
        const Expr& de = id < 0 ? dt : da;
        // Only where the function is smooth and well conditioned: two step
        // sizes must agree before the finite difference is trusted.
        bool degenerate = false;
        const double f0 = eval(e, env, &degenerate);
        if (degenerate) continue;
        const double h1 = central_diff(e, env, id, 1e-5), h2 = central_diff(e, env, id, 1e-4);
        if (!std::isfinite(h1) || !std::isfinite(h2)) continue;
        if (std::fabs(f0) > 1e6 || std::fabs(h1) > 1e6) continue;
        if (std::fabs(h1 - h2) > 1e-7 * (1 + std::fabs(h1))) continue;
        ++checked;
        const double d = eval(de, env);
        EXPECT_TRUE(std::fabs(d - h1) <= 1e-5 * (1 + std::fabs(h1)))
            << "d/d" << (id < 0 ? "t" : "a") << " " << str(e) << " = " << str(de) << ": " << d
            << " vs " << h1;
      }
    }
  }
  EXPECT_GT(checked, 3000);
}

}  // namespace
