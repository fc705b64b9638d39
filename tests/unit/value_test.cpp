// Unit tests for ir/value: lowering of expressions into shaped values — the
// matrix operators (products, elementwise + and -, unary minus, indexing) and
// the shaped built-ins (eye zeros transpose dot cross skew norm hcat vcat rotq
// quat_rate quat_mul quat_conj quat_axis_angle quat_arc bryant jacobian).
// Lowered expressions are evaluated numerically and checked against
// independent formulas (Rodrigues, rotation composition, finite differences),
// and every function's arity and shape errors are checked.
//
// Test suites are named value_* so that `ctest -R value` selects them.
#include "ir/value.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;
using Mat = std::vector<std::vector<double>>;
using Vec = std::vector<double>;

// ---- lowering with named variables -----------------------------------------------------

/// Names for lower(): each maps to a matrix of fresh Var leaves whose values
/// live in `env`.
struct Scope {
  std::map<std::string, ir::Value> values;
  Env env;
  int next = 0;

  /// A rows x cols matrix (row-major values) of fresh variables; returns their ids.
  std::vector<int> mat(const std::string& name, int rows, int cols, const Vec& x) {
    ir::Value v{rows, cols, {}};
    std::vector<int> ids;
    for (double xi : x) {
      int id = next++;
      env.vars[id] = xi;
      ids.push_back(id);
      v.items.push_back(ir::var(id));
    }
    values[name] = v;
    return ids;
  }
  std::vector<int> vec(const std::string& name, const Vec& x) { return mat(name, static_cast<int>(x.size()), 1, x); }
  int scalar(const std::string& name, double x) { return vec(name, {x})[0]; }
  void set(const std::vector<int>& ids, const Vec& x) {
    for (std::size_t i = 0; i < ids.size(); ++i) env.vars[ids[i]] = x[i];
  }
};

struct Lowered {
  std::unique_ptr<Compiled> c;
  std::optional<ir::Value> value;
};

/// Parses `expr` as a parameter's expression and lowers it with `s`'s names.
Lowered lower_text(const std::string& expr, const Scope& s) {
  Lowered out;
  out.c = run("param p = " + expr + "\n", Stage::Parse);
  if (!out.c->ok()) {
    ADD_FAILURE() << "parse error in `" << expr << "`:\n" << out.c->messages();
    return out;
  }
  const ir::AstExpr* e = nullptr;
  for (const ir::AstStmt& st : out.c->ast.stmts)
    if (auto* p = std::get_if<ir::AstParam>(&st)) e = p->value.get();
  if (!e) {
    ADD_FAILURE() << "no parameter parsed from `" << expr << "`";
    return out;
  }
  ir::Diagnostics& diags = out.c->diags;
  ir::NameLookup lookup = [&](const std::string& name, const ir::SourceLoc& loc) -> std::optional<ir::Value> {
    auto it = s.values.find(name);
    if (it != s.values.end()) return it->second;
    diags.error(loc, "unknown name `" + name + "`");
    return std::nullopt;
  };
  out.value = ir::lower(*e, lookup, diags);
  return out;
}

Mat evaluate(const ir::Value& v, const Env& env) {
  Mat m(static_cast<std::size_t>(v.rows), Vec(static_cast<std::size_t>(v.cols)));
  for (int i = 0; i < v.rows; ++i)
    for (int j = 0; j < v.cols; ++j) m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = eval(v.at(i, j), env);
  return m;
}

/// Lowers `expr` (which must succeed) to a Value.
ir::Value value_of(const std::string& expr, const Scope& s) {
  Lowered l = lower_text(expr, s);
  if (!l.value || !l.c->ok()) {
    ADD_FAILURE() << "`" << expr << "` did not lower:\n" << (l.c ? l.c->messages() : std::string());
    return ir::Value{0, 0, {}};
  }
  return *l.value;
}

/// Lowers and evaluates `expr` at the scope's values.
Mat num(const std::string& expr, const Scope& s) { return evaluate(value_of(expr, s), s.env); }

/// The rendered diagnostics of `expr`, which must fail with exactly one error
/// that has a hint.
std::string error_of(const std::string& expr, const Scope& s) {
  Lowered l = lower_text(expr, s);
  if (!l.c) return {};
  std::string text = l.c->messages();
  EXPECT_FALSE(l.value.has_value()) << "`" << expr << "` lowered without error";
  EXPECT_EQ(l.c->diags.error_count(), 1) << text;
  if (!l.c->diags.all().empty()) {
    EXPECT_FALSE(l.c->diags.all()[0].hint.empty()) << "no hint:\n" << text;
  }
  return text;
}

// ---- numeric helpers -------------------------------------------------------------------------

Mat col(const Vec& v) {
  Mat m;
  for (double x : v) m.push_back({x});
  return m;
}
Vec flat(const Mat& m) {
  Vec v;
  for (const Vec& r : m) v.insert(v.end(), r.begin(), r.end());
  return v;
}
Mat matmul(const Mat& a, const Mat& b) {
  Mat r(a.size(), Vec(b[0].size(), 0.0));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b[0].size(); ++j)
      for (std::size_t k = 0; k < b.size(); ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}
Mat transposed(const Mat& a) {
  Mat r(a[0].size(), Vec(a.size()));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < a[0].size(); ++j) r[j][i] = a[i][j];
  return r;
}
Mat identity(std::size_t n) {
  Mat r(n, Vec(n, 0.0));
  for (std::size_t i = 0; i < n; ++i) r[i][i] = 1;
  return r;
}
Mat lin(double a, const Mat& x, double b, const Mat& y) {  // a x + b y
  Mat r = x;
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t j = 0; j < r[i].size(); ++j) r[i][j] = a * x[i][j] + b * y[i][j];
  return r;
}
double det3(const Mat& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}
Mat skew_of(const Vec& v) { return {{0, -v[2], v[1]}, {v[2], 0, -v[0]}, {-v[1], v[0], 0}}; }
Mat rot_x(double a) { return {{1, 0, 0}, {0, std::cos(a), -std::sin(a)}, {0, std::sin(a), std::cos(a)}}; }
Mat rot_y(double a) { return {{std::cos(a), 0, std::sin(a)}, {0, 1, 0}, {-std::sin(a), 0, std::cos(a)}}; }
Mat rot_z(double a) { return {{std::cos(a), -std::sin(a), 0}, {std::sin(a), std::cos(a), 0}, {0, 0, 1}}; }
/// Rodrigues' formula: rotation by `angle` about `axis` (normalised here).
Mat rodrigues(Vec axis, double angle) {
  double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& a : axis) a /= n;
  Mat k = skew_of(axis);
  return lin(1, lin(1, identity(3), std::sin(angle), k), 1 - std::cos(angle), matmul(k, k));
}

::testing::AssertionResult near(const Mat& got, const Mat& want, double tol) {
  if (got.size() != want.size() || (!got.empty() && got[0].size() != want[0].size()))
    return ::testing::AssertionFailure() << "shape " << got.size() << "x" << (got.empty() ? 0 : got[0].size())
                                         << ", want " << want.size() << "x" << want[0].size();
  for (std::size_t i = 0; i < got.size(); ++i)
    for (std::size_t j = 0; j < got[i].size(); ++j)
      if (!(std::abs(got[i][j] - want[i][j]) <= tol))
        return ::testing::AssertionFailure() << "[" << i << "][" << j << "] = " << got[i][j] << ", want "
                                             << want[i][j] << " (tol " << tol << ")";
  return ::testing::AssertionSuccess();
}

Vec random_vec(std::mt19937& rng, std::size_t n, double lo = -1, double hi = 1) {
  std::uniform_real_distribution<double> u(lo, hi);
  Vec v(n);
  for (double& x : v) x = u(rng);
  return v;
}
/// A random quaternion of norm between 0.3 and 3 (deliberately not unit).
Vec random_quat(std::mt19937& rng) {
  Vec q = random_vec(rng, 4);
  double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  double scale = std::uniform_real_distribution<double>(0.3, 3.0)(rng);
  for (double& x : q) x *= scale / n;
  return q;
}

// ---- the existing operators on matrices --------------------------------------------------------

TEST(value_matrix, ProductsSumsNegationAndIndexing) {
  Scope s;
  s.vec("x", {1, -1, 2});
  s.mat("M", 2, 3, {1, 2, 3, 4, 5, 6});
  EXPECT_TRUE(near(num("[[1, 2], [3, 4]] * [[5, 6], [7, 8]]", s), {{19, 22}, {43, 50}}, 0));
  EXPECT_TRUE(near(num("M * x", s), col({5, 11}), 0));                       // matrix * vector
  EXPECT_TRUE(near(num("M * transpose(M)", s), {{14, 32}, {32, 77}}, 0));    // matrix * matrix
  EXPECT_TRUE(near(num("2 * M", s), {{2, 4, 6}, {8, 10, 12}}, 0));          // scalar * matrix
  EXPECT_TRUE(near(num("M * 2", s), {{2, 4, 6}, {8, 10, 12}}, 0));
  EXPECT_TRUE(near(num("M / 2", s), {{0.5, 1, 1.5}, {2, 2.5, 3}}, 0));
  EXPECT_TRUE(near(num("M + [[1, 1, 1], [2, 2, 2]]", s), {{2, 3, 4}, {6, 7, 8}}, 0));
  EXPECT_TRUE(near(num("M - [[1, 1, 1], [2, 2, 2]]", s), {{0, 1, 2}, {2, 3, 4}}, 0));
  EXPECT_TRUE(near(num("-M", s), {{-1, -2, -3}, {-4, -5, -6}}, 0));
  EXPECT_TRUE(near(num("-x + 2 * x", s), col({1, -1, 2}), 0));
  EXPECT_TRUE(near(num("x[2]", s), {{-1}}, 0));                              // 1-based
  EXPECT_TRUE(near(num("M[2, 3]", s), {{6}}, 0));
  EXPECT_TRUE(near(num("M[1, 2] + (M * x)[2]", s), {{13}}, 0));
  EXPECT_TRUE(near(num("transpose(x)[3]", s), {{2}}, 0));                    // a row vector indexes too
  EXPECT_TRUE(near(num("transpose(x) * x", s), {{6}}, 0));                   // 1x3 * 3x1 is a scalar
  EXPECT_TRUE(near(num("x * transpose(x)", s), {{1, -1, 2}, {-1, 1, -2}, {2, -2, 4}}, 0));

  EXPECT_NE(error_of("M * M", s).find("matrix product of a 2x3 matrix and a 2x3 matrix: inner dimensions differ"),
            std::string::npos);
  EXPECT_NE(error_of("x * x", s).find("inner dimensions differ"), std::string::npos);
  EXPECT_NE(error_of("M + eye(2)", s).find("cannot apply `+` to a 2x3 matrix and a 2x2 matrix"), std::string::npos);
  EXPECT_NE(error_of("eye(2) - x", s).find("cannot apply `-` to a 2x2 matrix and a 3-vector"), std::string::npos);
  EXPECT_NE(error_of("2 / x", s).find("cannot divide by a 3-vector"), std::string::npos);
  EXPECT_NE(error_of("M[3, 1]", s).find("index [3, 1] is out of range for a 2x3 matrix"), std::string::npos);
  EXPECT_NE(error_of("M[1]", s).find("a 2x3 matrix needs two indices"), std::string::npos);
  EXPECT_NE(error_of("x[4]", s).find("index 4 is out of range for a 3-vector"), std::string::npos);
}

// ---- construction and linear algebra -----------------------------------------------------------

TEST(value_matrix, EyeAndZeros) {
  Scope s;
  s.scalar("k", 2);
  EXPECT_TRUE(near(num("eye(3)", s), identity(3), 0));
  EXPECT_TRUE(near(num("eye(1 + 1)", s), identity(2), 0));  // any constant integer expression
  EXPECT_TRUE(near(num("zeros(2)", s), col({0, 0}), 0));    // zeros(r) is a column
  EXPECT_TRUE(near(num("zeros(2, 3)", s), {{0, 0, 0}, {0, 0, 0}}, 0));
  EXPECT_TRUE(near(num("k * eye(2) + zeros(2, 2)", s), {{2, 0}, {0, 2}}, 0));
  ir::Value z = value_of("zeros(3, 2)", s);
  EXPECT_EQ(z.rows, 3);
  EXPECT_EQ(z.cols, 2);
  for (const ir::Expr& e : z.items) EXPECT_TRUE(ir::is_zero(e));  // constants, foldable downstream
}

TEST(value_matrix, TransposeDotCrossSkewNorm) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    Scope s;
    Vec a = random_vec(rng, 3), b = random_vec(rng, 3);
    s.vec("a", a);
    s.vec("b", b);
    s.mat("M", 2, 3, random_vec(rng, 6));
    Vec c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    EXPECT_TRUE(near(num("cross(a, b)", s), col(c), 1e-15));
    EXPECT_TRUE(near(num("cross(transpose(a), b)", s), col(c), 1e-15));  // a row vector is accepted
    EXPECT_TRUE(near(num("skew(a)", s), skew_of(a), 0));
    EXPECT_TRUE(near(num("skew(a) * b", s), num("cross(a, b)", s), 1e-15));
    EXPECT_TRUE(near(num("dot(a, b)", s), {{ab}}, 1e-15));
    EXPECT_TRUE(near(num("dot(transpose(a), b)", s), {{ab}}, 1e-15));
    EXPECT_TRUE(near(num("norm(a)", s), {{std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])}}, 1e-15));
    EXPECT_TRUE(near(num("transpose(M)", s), transposed(num("M", s)), 0));
    EXPECT_TRUE(near(num("transpose(transpose(M))", s), num("M", s), 0));
  }
  Scope s;
  s.vec("a", {1, 2, 3});
  ir::Value t = value_of("transpose(a)", s);
  EXPECT_EQ(t.rows, 1);
  EXPECT_EQ(t.cols, 3);
  EXPECT_TRUE(near(num("norm([3, 4])", s), {{5}}, 0));
}

TEST(value_matrix, HcatAndVcat) {
  Scope s;
  s.vec("a", {1, 2});
  s.vec("b", {3, 4});
  EXPECT_TRUE(near(num("hcat(a, b)", s), {{1, 3}, {2, 4}}, 0));
  EXPECT_TRUE(near(num("hcat(eye(2), a, 5 * b)", s), {{1, 0, 1, 15}, {0, 1, 2, 20}}, 0));
  EXPECT_TRUE(near(num("vcat(a, b)", s), col({1, 2, 3, 4}), 0));
  EXPECT_TRUE(near(num("vcat(transpose(a), transpose(b), [[5, 6]])", s), {{1, 2}, {3, 4}, {5, 6}}, 0));
  EXPECT_TRUE(near(num("vcat(hcat(eye(2), a), hcat(transpose(b), 7))", s), {{1, 0, 1}, {0, 1, 2}, {3, 4, 7}}, 0));
  EXPECT_TRUE(near(num("hcat(a)", s), col({1, 2}), 0));
}

// ---- quaternions -------------------------------------------------------------------------------

TEST(value_quat, RotqIsAProperRotationForNonUnitQuaternions) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    Scope s;
    Vec q = random_quat(rng);
    s.vec("q", q);
    Mat r = num("rotq(q)", s);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_TRUE(near(matmul(transposed(r), r), identity(3), 1e-14)) << "q = " << q[0] << " " << q[1];
    EXPECT_NEAR(det3(r), 1.0, 1e-14);
    EXPECT_TRUE(near(num("rotq(3.5 * q)", s), r, 1e-15));                  // independent of |q|
    EXPECT_TRUE(near(num("rotq(quat_conj(q))", s), transposed(r), 1e-15));  // conjugate = inverse
    double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    EXPECT_TRUE(near(num("quat_mul(q, quat_conj(q))", s), col({n2, 0, 0, 0}), 1e-15));
    EXPECT_TRUE(near(num("quat_conj(q)", s), col({q[0], -q[1], -q[2], -q[3]}), 0));
  }
}

TEST(value_quat, AxisAngleMatchesRodrigues) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 50; ++trial) {
    Scope s;
    Vec axis = random_vec(rng, 3);
    for (double& x : axis) x *= 2.7;  // not normalised: quat_axis_angle normalises
    double angle = std::uniform_real_distribution<double>(-2 * M_PI, 2 * M_PI)(rng);
    s.vec("k", axis);
    s.scalar("a", angle);
    EXPECT_TRUE(near(num("rotq(quat_axis_angle(k, a))", s), rodrigues(axis, angle), 1e-14));
    EXPECT_TRUE(near(num("rotq(quat_axis_angle(transpose(k), a))", s), rodrigues(axis, angle), 1e-14));
    Mat q = num("quat_axis_angle(k, a)", s);
    EXPECT_NEAR(q[0][0] * q[0][0] + q[1][0] * q[1][0] + q[2][0] * q[2][0] + q[3][0] * q[3][0], 1.0, 1e-15);
    EXPECT_NEAR(q[0][0], std::cos(angle / 2), 1e-15);
  }
  // The convention spelled out: +90 degrees about z takes body x to inertial y.
  Scope s;
  EXPECT_TRUE(near(num("rotq(quat_axis_angle([0, 0, 1], pi / 2)) * [1, 0, 0]", s), col({0, 1, 0}), 1e-15));
  EXPECT_TRUE(near(num("rotq([cos(pi / 6), sin(pi / 6), 0, 0]) * [0, 1, 0]", s),
                   col({0, std::cos(M_PI / 3), std::sin(M_PI / 3)}), 1e-15));
}

TEST(value_quat, ProductComposesRotations) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 50; ++trial) {
    Scope s;
    Vec a = random_quat(rng), b = random_quat(rng);
    s.vec("a", a);
    s.vec("b", b);
    EXPECT_TRUE(near(num("rotq(quat_mul(a, b))", s), matmul(num("rotq(a)", s), num("rotq(b)", s)), 1e-14));
    // Hamilton's product written out: [a0 b0 - av.bv, a0 bv + b0 av + av x bv]
    Vec want{a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
             a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
             a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
             a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
    EXPECT_TRUE(near(num("quat_mul(a, b)", s), col(want), 1e-15));
    EXPECT_TRUE(near(num("quat_mul(transpose(a), b)", s), col(want), 1e-15));
  }
  Scope s;  // i j = k
  EXPECT_TRUE(near(num("quat_mul([0, 1, 0, 0], [0, 0, 1, 0])", s), col({0, 0, 0, 1}), 0));
}

TEST(value_quat, QuatRateIsTheBodyAngularVelocityKinematics) {
  std::mt19937 rng(19);
  for (int trial = 0; trial < 30; ++trial) {
    Scope s;
    Vec q = random_quat(rng), w = random_vec(rng, 3, -3, 3);
    auto qid = s.vec("q", q);
    s.vec("w", w);
    // The documented matrix, written out.
    Mat e = lin(0.5,
                {{-q[1], -q[2], -q[3]}, {q[0], -q[3], q[2]}, {q[3], q[0], -q[1]}, {-q[2], q[1], q[0]}}, 0,
                Mat(4, Vec(3, 0.0)));
    EXPECT_TRUE(near(num("quat_rate(q)", s), e, 0));
    // q' = 1/2 q (x) [0, omega] ...
    EXPECT_TRUE(near(num("quat_rate(q) * w", s), num("0.5 * quat_mul(q, vcat(0, w))", s), 1e-15));
    // ... keeps |q| constant ...
    EXPECT_NEAR(num("dot(q, quat_rate(q) * w)", s)[0][0], 0.0, 1e-14);
    // ... and makes d/dt rotq(q) = rotq(q) skew(omega), omega in body coordinates.
    ir::Value rot = value_of("rotq(q)", s);
    Vec qdot = flat(num("quat_rate(q) * w", s));
    const double h = 1e-6;
    Vec qp = q, qm = q;
    for (std::size_t i = 0; i < 4; ++i) {
      qp[i] += h * qdot[i];
      qm[i] -= h * qdot[i];
    }
    Scope sp = s, sm = s;
    sp.set(qid, qp);
    sm.set(qid, qm);
    Mat rdot = lin(0.5 / h, evaluate(rot, sp.env), -0.5 / h, evaluate(rot, sm.env));
    EXPECT_TRUE(near(rdot, num("rotq(q) * skew(w)", s), 1e-8));
    // (and not skew(omega) rotq(q), which would be omega in inertial coordinates)
    EXPECT_FALSE(near(rdot, num("skew(w) * rotq(q)", s), 1e-3));
  }
}

TEST(value_quat, ArcTakesZOntoTheDirectionForASweepOfDirections) {
  std::vector<Vec> dirs;
  for (int i = 0; i <= 36; ++i) {  // polar angle 0..pi, both ends exact
    double th = i == 36 ? M_PI : M_PI * i / 36;
    for (int j = 0; j < 24; ++j) {
      double ph = 2 * M_PI * j / 24;
      dirs.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  }
  for (double eps : {1e-1, 1e-4, 1e-8, 1e-12, 1e-20, 1e-100, 1e-149, 1e-151, 1e-160, 1e-200, 1e-310})
    for (double ph : {0.0, 0.7, 2.0, -2.5}) dirs.push_back({eps * std::cos(ph), eps * std::sin(ph), -1});
  dirs.push_back({0, 0, -1});
  dirs.push_back({0, 0, 1});
  dirs.push_back({1, 0, 0});
  dirs.push_back({0, -1, 0});
  dirs.push_back({1e-9, 0, -1 + 1e-16});
  Scope sym;  // lowered once, evaluated for every direction
  auto ids = sym.vec("a", {1, 1, 1});
  ir::Value arc = value_of("quat_arc(a)", sym), image = value_of("rotq(quat_arc(a)) * [0, 0, 1]", sym);
  int k = 0;
  for (const Vec& d : dirs) {
    for (double scale : {1.0, 1e-3, 250.0}) {
      Vec a{d[0] * scale, d[1] * scale, d[2] * scale};
      sym.set(ids, a);
      Mat q = evaluate(arc, sym.env);
      ASSERT_EQ(q.size(), 4u);
      double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      double c = a[2] / n;
      std::string what = "a = [" + std::to_string(a[0]) + ", " + std::to_string(a[1]) + ", " +
                         std::to_string(a[2]) + "], #" + std::to_string(k++);
      EXPECT_NEAR(q[0][0] * q[0][0] + q[1][0] * q[1][0] + q[2][0] * q[2][0] + q[3][0] * q[3][0], 1.0, 1e-14) << what;
      EXPECT_TRUE(near(evaluate(image, sym.env), col({a[0] / n, a[1] / n, a[2] / n}), 1e-14)) << what;
      // the shortest rotation: about an axis perpendicular to z and a, by acos(c)
      EXPECT_EQ(q[3][0], 0.0) << what;
      EXPECT_GE(q[0][0], 0.0) << what;
      EXPECT_NEAR(q[0][0], std::sqrt(std::max(0.0, (1 + c) / 2)), 1e-8) << what;
      EXPECT_NEAR(q[1][0] * a[0] + q[2][0] * a[1], 0.0, 1e-14 * n) << what;
    }
  }
  Scope s;
  s.vec("a", {0, 0, -3});
  EXPECT_TRUE(near(num("quat_arc(a)", s), col({0, 1, 0, 0}), 0));  // exactly -z: 180 degrees about +x
  s.vec("a", {0, 0, 2});
  EXPECT_TRUE(near(num("quat_arc(a)", s), col({1, 0, 0, 0}), 0));
  // constant arguments fold to constants
  for (const ir::Expr& e : value_of("quat_arc([0, 0, -1])", s).items) EXPECT_TRUE(ir::is_const(e));
  EXPECT_TRUE(near(num("quat_arc([1, 0, 0])", s), col({std::sqrt(0.5), 0, std::sqrt(0.5), 0}), 1e-15));
}

TEST(value_quat, BryantAnglesRoundTrip) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> any(-M_PI, M_PI), tilt(-M_PI / 2 + 0.01, M_PI / 2 - 0.01);
  for (int trial = 0; trial < 50; ++trial) {
    // angles -> quaternion (times a non-unit factor) -> angles
    Scope s;
    double phi = any(rng), theta = tilt(rng), psi = any(rng);
    s.scalar("ph", phi);
    s.scalar("th", theta);
    s.scalar("ps", psi);
    s.scalar("k", std::uniform_real_distribution<double>(0.3, 3)(rng));
    EXPECT_TRUE(near(num("bryant(k * quat_mul(quat_mul(quat_axis_angle([1, 0, 0], ph), "
                         "quat_axis_angle([0, 1, 0], th)), quat_axis_angle([0, 0, 1], ps)))",
                         s),
                     col({phi, theta, psi}), 1e-12));
    // quaternion -> angles -> Rx(phi) Ry(theta) Rz(psi) == rotq(q)
    Scope t;
    t.vec("q", random_quat(rng));
    Vec ang = flat(num("bryant(q)", t));
    ASSERT_EQ(ang.size(), 3u);
    EXPECT_TRUE(near(matmul(matmul(rot_x(ang[0]), rot_y(ang[1])), rot_z(ang[2])), num("rotq(q)", t), 1e-13));
  }
  // At the singularity theta = +-90 degrees rounding must not push asin out of its domain.
  for (double sign : {1.0, -1.0})
    for (int i = 0; i < 200; ++i) {
      Scope s;
      s.scalar("ph", 0.01 * i);
      s.scalar("k", 1 + 0.013 * i);
      Vec ang = flat(num("bryant(k * quat_mul(quat_axis_angle([1, 0, 0], ph), quat_axis_angle([0, 1, 0], " +
                             std::string(sign > 0 ? "" : "-") + "pi / 2)))",
                         s));
      ASSERT_EQ(ang.size(), 3u);
      EXPECT_TRUE(std::isfinite(ang[0]) && std::isfinite(ang[1]) && std::isfinite(ang[2])) << i;
      EXPECT_NEAR(ang[1], sign * M_PI / 2, 1e-7) << i;
    }
}

// ---- jacobian ----------------------------------------------------------------------------------

/// Central finite differences of the lowered vector `f` with respect to the
/// variables `ids` at the scope's values.
Mat fd_jacobian(const ir::Value& f, const Scope& s, const std::vector<int>& ids) {
  Vec f0 = flat(evaluate(f, s.env));
  Mat j(f0.size(), Vec(ids.size()));
  for (std::size_t c = 0; c < ids.size(); ++c) {
    const double h = 1e-6;
    Env ep = s.env, em = s.env;
    ep.vars[ids[c]] += h;
    em.vars[ids[c]] -= h;
    Vec fp = flat(evaluate(f, ep)), fm = flat(evaluate(f, em));
    for (std::size_t r = 0; r < f0.size(); ++r) j[r][c] = (fp[r] - fm[r]) / (2 * h);
  }
  return j;
}

TEST(value_jacobian, MatchesFiniteDifferences) {
  std::mt19937 rng(29);
  for (int trial = 0; trial < 20; ++trial) {
    Scope s;
    auto x = s.vec("x", random_vec(rng, 3));
    auto q = s.vec("q", random_quat(rng));
    const std::string f = "[x[1] * sin(x[2]), x[1]^2 + x[3], exp(x[2] * x[3]), atan2(x[3], x[1])]";
    Mat j = num("jacobian(" + f + ", x)", s);
    ASSERT_EQ(j.size(), 4u);
    ASSERT_EQ(j[0].size(), 3u);
    EXPECT_TRUE(near(j, fd_jacobian(value_of(f, s), s, x), 1e-8));
    // columns follow the order of the variables given
    EXPECT_TRUE(near(num("jacobian(" + f + ", [x[3], x[1]])", s),
                     fd_jacobian(value_of(f, s), s, {x[2], x[0]}), 1e-8));
    // a matrix-valued chain: d(rotq(q) r)/dq, 3x4
    Mat jq = num("jacobian(rotq(q) * [1, 2, 3], q)", s);
    EXPECT_TRUE(near(jq, fd_jacobian(value_of("rotq(q) * [1, 2, 3]", s), s, q), 1e-7));
    // a scalar f gives one row; rows or columns are accepted for both arguments
    EXPECT_TRUE(near(num("jacobian(dot(x, x), transpose(x))", s), transposed(num("2 * x", s)), 1e-15));
    EXPECT_TRUE(near(num("jacobian(transpose(x), x)", s), identity(3), 0));
  }
}

TEST(value_jacobian, SecondArgumentMustBeVariables) {
  Scope s;
  s.vec("x", {1, 2, 3});
  const char* msg = "jacobian's second argument must be model variables (e.g. a C element's q)";
  EXPECT_NE(error_of("jacobian(x, [x[1], 2])", s).find(msg), std::string::npos);
  EXPECT_NE(error_of("jacobian(x, 2 * x)", s).find(msg), std::string::npos);
  EXPECT_NE(error_of("jacobian(x, -x)", s).find(msg), std::string::npos);
  EXPECT_NE(error_of("jacobian(x, [x[1] + x[2]])", s).find(msg), std::string::npos);
  EXPECT_NE(error_of("jacobian(x, hcat(x, x))", s).find("`jacobian` expects a vector of model variables as "
                                                         "argument 2, this is a 3x2 matrix"),
            std::string::npos);
  EXPECT_NE(error_of("jacobian(eye(2), x)", s).find("`jacobian` expects a vector of expressions as argument 1, "
                                                     "this is a 2x2 matrix"),
            std::string::npos);
}

// ---- diagnostics -------------------------------------------------------------------------------

TEST(value_errors, ArityOfEveryShapedFunction) {
  Scope s;
  s.vec("x", {1, 2, 3});
  s.vec("q", {1, 0, 0, 0});
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"eye()", "`eye` takes 1 argument, but 0 were given"},
      {"eye(2, 3)", "`eye` takes 1 argument, but 2 were given"},
      {"zeros()", "`zeros` takes 1 to 2 arguments, but 0 were given"},
      {"zeros(1, 2, 3)", "`zeros` takes 1 to 2 arguments, but 3 were given"},
      {"transpose(x, x)", "`transpose` takes 1 argument, but 2 were given"},
      {"dot(x)", "`dot` takes 2 arguments, but 1 was given"},
      {"cross(x, x, x)", "`cross` takes 2 arguments, but 3 were given"},
      {"skew(x, x)", "`skew` takes 1 argument, but 2 were given"},
      {"norm()", "`norm` takes 1 argument, but 0 were given"},
      {"hcat()", "`hcat` takes 1 to 1000 arguments, but 0 were given"},
      {"vcat()", "`vcat` takes 1 to 1000 arguments, but 0 were given"},
      {"rotq(q, q)", "`rotq` takes 1 argument, but 2 were given"},
      {"quat_rate()", "`quat_rate` takes 1 argument, but 0 were given"},
      {"quat_mul(q)", "`quat_mul` takes 2 arguments, but 1 was given"},
      {"quat_conj(q, q)", "`quat_conj` takes 1 argument, but 2 were given"},
      {"quat_axis_angle(x)", "`quat_axis_angle` takes 2 arguments, but 1 was given"},
      {"quat_arc(x, x)", "`quat_arc` takes 1 argument, but 2 were given"},
      {"bryant()", "`bryant` takes 1 argument, but 0 were given"},
      {"jacobian(x)", "`jacobian` takes 2 arguments, but 1 was given"},
  };
  for (const auto& [expr, want] : cases) EXPECT_NE(error_of(expr, s).find(want), std::string::npos) << expr << " / " << want;
}

TEST(value_errors, ShapeOfEveryShapedFunction) {
  Scope s;
  s.vec("x", {1, 2, 3});
  s.vec("q", {1, 0, 0, 0});
  s.scalar("u", 2);
  const std::string quat = "a quaternion (a 4-vector [w, x, y, z])";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"eye(2.5)", "`eye` needs a constant integer from 1 to 1000 here"},
      {"eye(u)", "`eye` needs a constant integer from 1 to 1000 here"},
      {"eye(0)", "`eye` needs a constant integer from 1 to 1000 here"},
      {"eye([2, 2])", "`eye` needs a constant integer from 1 to 1000 here"},
      {"zeros(100000)", "`zeros` needs a constant integer from 1 to 1000 here"},
      {"zeros(2, -1)", "`zeros` needs a constant integer from 1 to 1000 here"},
      {"dot(x, q)", "`dot` expects a 3-vector (like argument 1) as argument 2, this is a 4-vector"},
      {"dot(eye(2), x)", "`dot` expects a vector as argument 1, this is a 2x2 matrix"},
      {"cross(x, [1, 2])", "`cross` expects a 3-vector as argument 2, this is a 2-vector"},
      {"cross(q, x)", "`cross` expects a 3-vector as argument 1, this is a 4-vector"},
      {"skew(q)", "`skew` expects a 3-vector as its argument, this is a 4-vector"},
      {"skew(u)", "`skew` expects a 3-vector as its argument, this is a scalar"},
      {"norm(eye(2))", "`norm` expects a vector as its argument, this is a 2x2 matrix"},
      {"hcat(eye(2), x)", "`hcat` of a 2x2 matrix and a 3-vector: the row counts differ (2 and 3)"},
      {"vcat(eye(2), x)", "`vcat` of a 2x2 matrix and a 3-vector: the column counts differ (2 and 1)"},
      {"rotq(x)", "`rotq` expects " + quat + " as its argument, this is a 3-vector"},
      {"quat_rate(eye(4))", "`quat_rate` expects " + quat + " as its argument, this is a 4x4 matrix"},
      {"quat_mul(q, x)", "`quat_mul` expects " + quat + " as argument 2, this is a 3-vector"},
      {"quat_mul(x, q)", "`quat_mul` expects " + quat + " as argument 1, this is a 3-vector"},
      {"quat_conj(u)", "`quat_conj` expects " + quat + " as its argument, this is a scalar"},
      {"quat_axis_angle(q, u)", "`quat_axis_angle` expects a 3-vector (the axis) as argument 1, this is a 4-vector"},
      {"quat_axis_angle(x, x)", "`quat_axis_angle` expects a scalar angle as argument 2, this is a 3-vector"},
      {"quat_arc(q)", "`quat_arc` expects a 3-vector as its argument, this is a 4-vector"},
      {"bryant(x)", "`bryant` expects " + quat + " as its argument, this is a 3-vector"},
      {"jacobian(x, eye(2))", "`jacobian` expects a vector of model variables as argument 2, this is a 2x2 matrix"},
      {"sin(x)", "`sin` expects scalar arguments, this is a 3-vector"},
  };
  for (const auto& [expr, want] : cases) EXPECT_NE(error_of(expr, s).find(want), std::string::npos) << expr << " / " << want;
}

TEST(value_errors, NamesAreKnownAndSuggested) {
  std::vector<std::string> names = ir::function_names();
  for (const char* f : {"eye", "zeros", "transpose", "dot", "cross", "skew", "norm", "hcat", "vcat", "rotq",
                        "quat_rate", "quat_mul", "quat_conj", "quat_axis_angle", "quat_arc", "bryant", "jacobian"})
    EXPECT_NE(std::find(names.begin(), names.end(), f), names.end()) << f;
  Scope s;
  s.vec("q", {1, 0, 0, 0});
  EXPECT_NE(error_of("quat_mull(q, q)", s).find("did you mean `quat_mul`?"), std::string::npos);
  EXPECT_NE(error_of("jacobain(q, q)", s).find("did you mean `jacobian`?"), std::string::npos);
  EXPECT_NE(error_of("trnaspose(q)", s).find("did you mean `transpose`?"), std::string::npos);
  EXPECT_NE(error_of("sinn(1)", s).find("did you mean `sign`?"), std::string::npos);  // unchanged
}

}  // namespace
