// Unit tests for pass 6 (reduce): alias elimination, derivative causality
// eliminated symbolically, sorting, linear algebraic loops solved (checked
// numerically against hand-solved circuits by evaluating the assignments in
// order), nonlinear implicit laws giving a DAE, and dead-equation removal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;

std::unique_ptr<Compiled> reduce(const std::string& text) { return run(text, Stage::Reduce); }

double output_value(const ir::ReducedSystem& r, const Env& env, const std::string& name) {
  for (const ir::Output& o : r.graph.outputs)
    if (o.name == name) return eval(o.value, env);
  ADD_FAILURE() << "no output " << name;
  return NAN;
}

std::vector<std::string> assigned(const ir::ReducedSystem& r) {
  std::vector<std::string> out;
  for (const ir::Assignment& a : r.assignments) out.push_back(r.graph.vars[static_cast<std::size_t>(a.var)].name);
  return out;
}

bool any_der(const ir::ReducedSystem& r) {
  for (const ir::Assignment& a : r.assignments)
    if (ir::contains_der(a.value)) return true;
  for (const ir::Expr& e : r.state_derivative)
    if (ir::contains_der(e)) return true;
  for (const ir::Residual& res : r.residuals)
    if (ir::contains_der(res.value)) return true;
  for (const ir::Output& o : r.graph.outputs)
    if (ir::contains_der(o.value)) return true;
  return false;
}

const char* kSeriesRlc =
    "param V = 5\nSe src = V\nR r = 2\nI l = 0.5\nC c = 0.1\n1 loop : src -> r, l, c\noutput i = l.f\noutput vc = c.e\n";

const char* kAlgebraicLoop =
    "param V = 10\nparam R1 = 1.5\nparam R2 = 2.5\nparam R3 = 4\nparam C = 0.5\n"
    "Se src = V\nR r1 = R1\nR r2 = R2\nR r3 = R3\nC cap = C\n"
    "1 s : src -> r1, n\n0 n : -> r2, m\n1 m : -> r3, cap\n"
    "output i1 = r1.f\noutput i2 = r2.f\noutput vn = n.e\n";

const char* kTwoInertias =
    "param F = 2\nparam m1 = 1\nparam m2 = 3\n"
    "Se force = F\nI mass1 = m1\nI mass2 = m2\n1 v : force -> mass1, mass2\n"
    "output v1 = mass1.f\noutput f1 = mass1.e\noutput f2 = mass2.e\n";

const char* kNonlinearDae =
    "Se src = sine(1, 1)\nR diode { e = 0.1*f + f^3 }\nR leak = 10\nC cap = 0.01\n1 s : src -> diode, n\n"
    "0 n : -> leak, cap\noutput vc = cap.e\noutput i = diode.f\n";

// ---- alias elimination ------------------------------------------------------------------------------

TEST(ReduceAliases, SeriesRlcRemovesFiveAliases) {
  auto c = reduce(kSeriesRlc);
  ASSERT_TRUE(c->ok()) << c->messages();
  // der(l.p) = l.e, der(c.q) = c.f, and the three "equal flows" of the 1-junction.
  EXPECT_EQ(alias_count(c->reduced), 5);
  EXPECT_EQ(assigned(c->reduced), (std::vector<std::string>{"src.e", "l.f", "r.e", "c.e", "l.e"}));
  EXPECT_TRUE(c->reduced.loops.empty());
  // The integrator gets the aliases' targets.
  ASSERT_EQ(c->reduced.state_derivative.size(), 2u);
  EXPECT_EQ(str(c->reduced.state_derivative[0], c->reduced.graph), "l.e");
  EXPECT_EQ(str(c->reduced.state_derivative[1], c->reduced.graph), "l.f");
}

TEST(ReduceAliases, AlgebraicLoopModelRemovesEightAliases) {
  auto c = reduce(
      "Se src = 10\nR r1 = 1\nR r2 = 2\nR r3 = 3\nC cap = 0.5\n1 s : src -> r1, n\n0 n : -> r2, m\n1 m : -> r3, cap\n"
      "output vc = cap.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  // r1.e = r1.f (R = 1 folds away), der(cap.q) = cap.f, two equal flows at s, two equal efforts
  // at n, two equal flows at m.
  EXPECT_EQ(alias_count(c->reduced), 8);
}

TEST(ReduceAliases, NegatedAliasKeepsItsSign) {
  // (A parameter, not a literal: a literal source would make every variable a constant.)
  auto c = reduce("param V = 10\nSe src = V\nR r = 2\n1 j : src ->\nbond r -> j\noutput fr = r.f\noutput er = r.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_EQ(alias_count(c->reduced), 1);  // src.f = r.f
  Env env = evaluate(c->reduced, {});
  EXPECT_DOUBLE_EQ(output_value(c->reduced, env, "er"), -10.0);
  EXPECT_DOUBLE_EQ(output_value(c->reduced, env, "fr"), -5.0);  // e = R f for the element: -10 = 2 * (-5)
}

// ---- sorting and evaluation order ------------------------------------------------------------------

TEST(ReduceSort, SeriesRlcNumerically) {
  auto c = reduce(kSeriesRlc);
  ASSERT_TRUE(c->ok()) << c->messages();
  const double p = 0.2, q = 0.03;  // l.p, c.q
  Env env = evaluate(c->reduced, {{"l.p", p}, {"c.q", q}});
  const double i = p / 0.5, vc = q / 0.1;
  EXPECT_NEAR(eval(c->reduced.state_derivative[0], env), 5 - 2 * i - vc, 1e-12);  // L di/dt
  EXPECT_NEAR(eval(c->reduced.state_derivative[1], env), i, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "i"), i, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "vc"), vc, 1e-12);
}

TEST(ReduceSort, ReversedBondsMirrorTheSeriesRlc) {
  // The same circuit with the R, I and C bonds pointing into the junction: the
  // elements see the loop current with the opposite sign, so at mirrored states
  // the state derivatives are mirrored too.
  auto fwd = reduce(kSeriesRlc);
  auto rev = reduce("Se src = 5\nR r = 2\nI l = 0.5\nC c = 0.1\n1 loop : src, r, l, c ->\n"
                    "output i = l.f\noutput vc = c.e\n");
  ASSERT_TRUE(fwd->ok()) << fwd->messages();
  ASSERT_TRUE(rev->ok()) << rev->messages();
  const double p = 0.2, q = 0.03;
  Env ef = evaluate(fwd->reduced, {{"l.p", p}, {"c.q", q}});
  Env er = evaluate(rev->reduced, {{"l.p", -p}, {"c.q", -q}});
  ASSERT_EQ(rev->reduced.state_derivative.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_NEAR(eval(rev->reduced.state_derivative[k], er), -eval(fwd->reduced.state_derivative[k], ef), 1e-12);
  EXPECT_NEAR(output_value(rev->reduced, er, "i"), -output_value(fwd->reduced, ef, "i"), 1e-12);
  EXPECT_NEAR(output_value(rev->reduced, er, "vc"), -output_value(fwd->reduced, ef, "vc"), 1e-12);
}

TEST(ReduceSort, PowerBalanceHoldsWithReversedTwoPortBonds) {
  // GY with both ports reversed, TF with p1 reversed: the sources' power must
  // equal what R, I and C take in, and each two-port must conserve power.
  auto c = reduce(
      "Se src = 3\nR ra = 0.5\nI la = 0.1\nGY g = 0.7\nI jm = 0.2\nR b = 0.3\nTF t = 2\nC k = 0.05\nR rk = 4\n"
      "1 a : src -> ra, la\nbond g.p1 -> a\n1 s : -> jm, b\nbond s -> g.p2\nbond t.p1 -> s\n"
      "0 z : -> k, rk\nbond t.p2 -> z\n"
      "output balance = src.e*src.f - (ra.e*ra.f + la.e*la.f + jm.e*jm.f + b.e*b.f + k.e*k.f + rk.e*rk.f)\n"
      "output pg = g.e1*g.f1 - g.e2*g.f2\noutput pt = t.e1*t.f1 - t.e2*t.f2\noutput pj = jm.e*jm.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->reduced.states.size(), 3u);
  for (const auto& st : std::vector<std::map<std::string, double>>{
           {{"la.p", 0.3}, {"jm.p", -0.7}, {"k.q", 0.11}}, {{"la.p", -2.0}, {"jm.p", 0.5}, {"k.q", -0.4}}}) {
    Env env = evaluate(c->reduced, st);
    EXPECT_NEAR(output_value(c->reduced, env, "balance"), 0.0, 1e-12);
    EXPECT_NEAR(output_value(c->reduced, env, "pg"), 0.0, 1e-12);
    EXPECT_NEAR(output_value(c->reduced, env, "pt"), 0.0, 1e-12);
    EXPECT_GT(std::fabs(output_value(c->reduced, env, "pj")), 1e-3);  // the check is not vacuous
  }
}

TEST(ReduceSort, PowerBalanceThroughANonSquareTransformer) {
  auto c = reduce(
      "Sf src = [1, 2, 3]\nTF t = [[1, 0, 2], [0, 1, 1]]\nR r = [[2, 1], [1, 3]]\n1 a : src -> t\n1 b : t -> r\n"
      "output bal = src.e[1]*src.f[1] + src.e[2]*src.f[2] + src.e[3]*src.f[3] - (r.e[1]*r.f[1] + r.e[2]*r.f[2])\n"
      "output f = r.f\noutput e = src.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  Env env = evaluate(c->reduced, {});
  EXPECT_NEAR(output_value(c->reduced, env, "bal"), 0.0, 1e-12);
  // f2 = T f1 = [1 + 6, 2 + 3]; e1 = T' R f2 = T' [2*7 + 5, 7 + 3*5] = T' [19, 22].
  EXPECT_NEAR(output_value(c->reduced, env, "f[1]"), 7.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "f[2]"), 5.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e[1]"), 19.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e[2]"), 22.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e[3]"), 2 * 19.0 + 22.0, 1e-12);
}

TEST(ReduceSort, SquareTransformerInReverseCausalityIsInverted) {
  // The flow source sits on p2, so the TF computes f1 from f2 and e2 from e1:
  // with a full T both are 2x2 linear loops, solved symbolically.
  auto c = reduce("Sf s = [1, 2]\nTF t = [[2, 1], [1, 1]]\nR r = diag(1, 2)\n1 b : s ->\nbond t.p2 -> b\n"
                  "1 a : -> r\nbond a -> t.p1\noutput f1 = t.f1\noutput e1 = t.e1\noutput e2 = t.e2\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  ASSERT_EQ(c->reduced.loops.size(), 2u);
  EXPECT_TRUE(c->reduced.loops[0].linear && c->reduced.loops[1].linear);
  Env env = evaluate(c->reduced, {});
  // f1 = T^-1 [1, 2] = [-1, 3]; e1 = -R f1 (both bonds leave a) = [1, -6]; e2 = T'^-1 e1 = [7, -13].
  EXPECT_NEAR(output_value(c->reduced, env, "f1[1]"), -1.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "f1[2]"), 3.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e1[1]"), 1.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e1[2]"), -6.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e2[1]"), 7.0, 1e-12);
  EXPECT_NEAR(output_value(c->reduced, env, "e2[2]"), -13.0, 1e-12);
}

/// True if some node of e has only constant operands (a fold that was missed).
bool has_unfolded_constants(const ir::Expr& e) {
  if (e->args.empty()) return false;
  bool all_const = true;
  for (const ir::Expr& a : e->args) all_const = all_const && a->op == ir::Op::Const;
  if (all_const && !(e->op == ir::Op::Div && ir::is_zero(e->args[1]))) return true;
  for (const ir::Expr& a : e->args)
    if (has_unfolded_constants(a)) return true;
  return false;
}

TEST(ReduceSort, ConstantsAreFolded) {
  auto c = reduce("param k = 3\nSe src = 2 * 3 + 1\nR r = 7\nR q = k * 2\n1 j : src -> r, q\noutput i = r.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  for (const ir::Assignment& a : c->reduced.assignments)
    EXPECT_FALSE(has_unfolded_constants(a.value)) << str(a.value, c->reduced.graph);
  Env env = evaluate(c->reduced, {});
  EXPECT_NEAR(output_value(c->reduced, env, "i"), 7.0 / 13.0, 1e-12);
}

// ---- linear algebraic loops ---------------------------------------------------------------------------

TEST(ReduceLoops, LinearLoopIsSolvedSymbolically) {
  auto c = reduce(kAlgebraicLoop);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  EXPECT_FALSE(r.dae);
  ASSERT_EQ(r.loops.size(), 1u);
  EXPECT_TRUE(r.loops[0].linear);
  EXPECT_EQ(r.loops[0].resolution, "linear: solved symbolically (Gaussian elimination)");
  std::vector<int> numbers;
  for (int b : r.loops[0].bonds) numbers.push_back(r.graph.bonds[static_cast<std::size_t>(b)].number);
  // r1 (R1 = 1.5, so not an alias) closes the loop with r2 and the r3-cap branch.
  EXPECT_EQ(numbers, (std::vector<int>{2, 3, 4, 6}));
  EXPECT_EQ(r.loops[0].vars.size(), 6u);
  EXPECT_FALSE(any_der(r));
}

TEST(ReduceLoops, LinearLoopMatchesTheHandSolvedCircuit) {
  auto c = reduce(kAlgebraicLoop);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  const double V = 10, R1 = 1.5, R2 = 2.5, R3 = 4, C = 0.5;
  for (double q : {0.0, 0.3, -1.2, 4.0}) {
    Env env = evaluate(r, {{"cap.q", q}});
    // Node voltage vn from (V - vn)/R1 = vn/R2 + (vn - vc)/R3.
    const double vc = q / C;
    const double vn = (V / R1 + vc / R3) / (1 / R1 + 1 / R2 + 1 / R3);
    const double i3 = (vn - vc) / R3;
    EXPECT_NEAR(eval(r.state_derivative[0], env), i3, 1e-12) << "q = " << q;
    EXPECT_NEAR(output_value(r, env, "vn"), vn, 1e-12) << "q = " << q;
    EXPECT_NEAR(output_value(r, env, "i1"), (V - vn) / R1, 1e-12) << "q = " << q;
    EXPECT_NEAR(output_value(r, env, "i2"), vn / R2, 1e-12) << "q = " << q;
  }
}

TEST(ReduceLoops, LoopWithParametersFollowsParameterValues) {
  // The loop is solved symbolically, so the same assignments must be right for
  // other parameter values (as --set would give them).
  auto c = reduce(kAlgebraicLoop);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  Env env;
  env.params = param_values(r.graph);
  env.params[param_id(r.graph, "R1")] = 3.0;
  env.params[param_id(r.graph, "R2")] = 6.0;
  env.vars[var_id(r.graph, "cap.q")] = 0.0;
  for (const ir::Assignment& a : r.assignments) env.vars[a.var] = eval(a.value, env);
  // vc = 0: vn = V/R1 / (1/R1 + 1/R2 + 1/R3) = (10/3) / (1/3 + 1/6 + 1/4) = 40/9
  EXPECT_NEAR(output_value(r, env, "vn"), 40.0 / 9.0, 1e-12);
  EXPECT_NEAR(eval(r.state_derivative[0], env), 10.0 / 9.0, 1e-12);
}

// ---- derivative causality ----------------------------------------------------------------------------

TEST(ReduceDerivative, TwoInertiasAccelerateAsOneMass) {
  auto c = reduce(kTwoInertias);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.states.size(), 1u);
  EXPECT_EQ(r.graph.vars[static_cast<std::size_t>(r.states[0].var)].name, "mass1.p");
  ASSERT_EQ(r.derivative_causality.size(), 1u);
  EXPECT_EQ(r.derivative_causality[0],
            "I mass2: e = der(p) (derivative causality): state eliminated, derivative taken symbolically");
  EXPECT_FALSE(any_der(r));
  EXPECT_FALSE(r.dae);
  const double F = 2, m1 = 1, m2 = 3;
  for (double p : {0.0, 1.5}) {
    Env env = evaluate(r, {{"mass1.p", p}});
    const double a = eval(r.state_derivative[0], env) / m1;  // dv/dt = (dp1/dt) / m1
    EXPECT_NEAR(a, F / (m1 + m2), 1e-12);
    EXPECT_NEAR(output_value(r, env, "f1"), m1 * F / (m1 + m2), 1e-12);
    EXPECT_NEAR(output_value(r, env, "f2"), m2 * F / (m1 + m2), 1e-12);
    EXPECT_NEAR(output_value(r, env, "v1"), p / m1, 1e-12);
  }
}

TEST(ReduceDerivative, TwoInertiasWithOtherParameterValues) {
  auto c = reduce(kTwoInertias);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  Env env;
  env.params = param_values(r.graph);
  env.params[param_id(r.graph, "F")] = 7.0;
  env.params[param_id(r.graph, "m1")] = 2.5;
  env.params[param_id(r.graph, "m2")] = 0.5;
  env.vars[var_id(r.graph, "mass1.p")] = 0.0;
  for (const ir::Assignment& a : r.assignments) env.vars[a.var] = eval(a.value, env);
  EXPECT_NEAR(eval(r.state_derivative[0], env) / 2.5, 7.0 / 3.0, 1e-12);
}

TEST(ReduceDerivative, InertiasCoupledThroughAGear) {
  auto c = reduce(
      "param F = 2\nparam m1 = 1\nparam m2 = 3\nparam n = 2\n"
      "Se force = F\nI a = m1\nTF g = n\nI b = m2\n1 j1 : force -> a, g\n1 j2 : g -> b\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.states.size(), 1u);
  Env env = evaluate(r, {{"a.p", 0.4}});
  // v_b = n v_a, so the reflected mass is n^2 m2.
  EXPECT_NEAR(eval(r.state_derivative[0], env) / 1.0, 2.0 / (1.0 + 4.0 * 3.0), 1e-12);
}

TEST(ReduceDerivative, TwoCapacitorsShareTheSourceFlow) {
  auto c = reduce("param I0 = 2\nSf src = I0\nC c1 = 0.5\nC c2 = 1.5\n0 n : src -> c1, c2\n"
                  "output v = c1.e\noutput q2 = c2.q\noutput i2 = c2.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.states.size(), 1u);
  Env env = evaluate(r, {{"c1.q", 0.25}});
  EXPECT_NEAR(eval(r.state_derivative[0], env), 2.0 * 0.5 / (0.5 + 1.5), 1e-12);
  EXPECT_NEAR(output_value(r, env, "v"), 0.5, 1e-12);
  EXPECT_NEAR(output_value(r, env, "q2"), 1.5 * 0.5, 1e-12);  // same voltage on both
  EXPECT_NEAR(output_value(r, env, "i2"), 2.0 * 1.5 / 2.0, 1e-12);
}

TEST(ReduceDerivative, TimeDependentInputIsDifferentiatedInTime) {
  auto c = reduce("Sf drive = sin(3 * t)\nI m = 2\n1 v : drive -> m\noutput e = m.e\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  EXPECT_TRUE(r.states.empty());
  for (double t : {0.0, 0.7, 2.0}) {
    Env env = evaluate(r, {}, t);
    EXPECT_NEAR(output_value(r, env, "e"), 2 * 3 * std::cos(3 * t), 1e-12) << "t = " << t;
  }
}

// ---- nonlinear implicit laws: DAE ----------------------------------------------------------------------

TEST(ReduceDae, NonlinearImplicitLawMakesADae) {
  auto c = reduce(kNonlinearDae);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  EXPECT_TRUE(r.dae);
  ASSERT_EQ(r.states.size(), 1u);
  ASSERT_EQ(r.algebraic.size(), 1u);
  EXPECT_EQ(r.graph.vars[static_cast<std::size_t>(r.algebraic[0])].name, "diode.f");
  EXPECT_EQ(r.residuals.size(), r.states.size() + r.algebraic.size());
  ASSERT_EQ(r.derivative_unknowns.size(), 1u);
  ASSERT_GE(r.derivative_unknowns[0], 0);
  EXPECT_EQ(r.graph.vars[static_cast<std::size_t>(r.derivative_unknowns[0])].name, "yp(cap.q)");
  ASSERT_EQ(r.loops.size(), 1u);
  EXPECT_FALSE(r.loops[0].linear);
  EXPECT_EQ(r.loops[0].resolution, "nonlinear: left to IDA as a DAE (residuals)");
  ASSERT_EQ(r.loops[0].bonds.size(), 1u);
  EXPECT_EQ(r.graph.bonds[static_cast<std::size_t>(r.loops[0].bonds[0])].number, 2);
  // The algebraic unknown is read, never assigned.
  for (const ir::Assignment& a : r.assignments) EXPECT_NE(a.var, r.algebraic[0]);
}

TEST(ReduceDae, ResidualsVanishAtAConsistentPoint) {
  auto c = reduce(kNonlinearDae);
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.residuals.size(), 2u);
  const double t = 0.1, q = 0.005, f = 0.3;
  const double vc = q / 0.01;
  const double e_diode = std::sin(2 * M_PI * 1 * t) - vc;
  const double dq = f - vc / 10;
  Env env = evaluate(r, {{"cap.q", q}, {"diode.f", f}, {"yp(cap.q)", dq}}, t);
  EXPECT_NEAR(eval(r.residuals[0].value, env), 0.0, 1e-12);
  EXPECT_NEAR(eval(r.residuals[1].value, env), e_diode - (0.1 * f + f * f * f), 1e-12);
  // A consistent diode current makes the algebraic residual vanish (bisection on f).
  double lo = -5, hi = 5;
  for (int k = 0; k < 200; ++k) {
    double mid = (lo + hi) / 2;
    Env e = evaluate(r, {{"cap.q", q}, {"diode.f", mid}, {"yp(cap.q)", 0}}, t);
    (eval(r.residuals[1].value, e) > 0 ? lo : hi) = mid;
  }
  Env e = evaluate(r, {{"cap.q", q}, {"diode.f", lo}, {"yp(cap.q)", 0}}, t);
  EXPECT_NEAR(0.1 * lo + lo * lo * lo, e_diode, 1e-9);
  EXPECT_NEAR(output_value(r, e, "i"), lo, 1e-15);
}

TEST(ReduceDae, ConductanceLawForcedIntoResistanceForm) {
  auto c = reduce("Se src = 1\nI l = 2\nR d { f = e^3 }\n1 j : src -> l, d\noutput i = l.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  EXPECT_TRUE(r.dae);
  ASSERT_EQ(r.algebraic.size(), 1u);
  EXPECT_EQ(r.graph.vars[static_cast<std::size_t>(r.algebraic[0])].name, "d.e");
  EXPECT_EQ(r.residuals.size(), 2u);
  Env env = evaluate(r, {{"l.p", 2.0}, {"d.e", 1.0}, {"yp(l.p)", 0.0}});
  EXPECT_NEAR(eval(r.residuals[1].value, env), 0.0, 1e-12);  // f = 1 = 1^3
  EXPECT_NEAR(eval(r.residuals[0].value, env), 0.0 - (1.0 - 1.0), 1e-12);
}

TEST(ReduceDae, OdeModelsHaveNoResiduals) {
  auto c = reduce(kSeriesRlc);
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_FALSE(c->reduced.dae);
  EXPECT_TRUE(c->reduced.residuals.empty());
  EXPECT_TRUE(c->reduced.algebraic.empty());
}

// ---- slicing --------------------------------------------------------------------------------------

TEST(ReduceSlice, OnlyWhatDerivativesAndOutputsNeedIsKept) {
  auto c = reduce("param F = 2\nparam m1 = 1\nparam m2 = 3\n"
                  "Se force = F\nI mass1 = m1\nI mass2 = m2\n1 v : force -> mass1, mass2\noutput v1 = mass1.f\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  // mass2 is in derivative causality: its momentum's rate is a variable of its own
  EXPECT_EQ(assigned(r), (std::vector<std::string>{"force.e", "mass1.f", "der(mass2.p)", "mass1.e"}));
  EXPECT_EQ(r.for_derivative, (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(r.for_outputs, (std::vector<int>{1}));
  EXPECT_NE(std::find(r.log.begin(), r.log.end(), "dead-equation removal: 3 assignments nothing needs removed"),
            r.log.end());
}

class ReduceInvariants : public ::testing::TestWithParam<const char*> {};

TEST_P(ReduceInvariants, AssignmentsReadOnlyWhatIsKnownBefore) {
  auto c = reduce(GetParam());
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  std::set<int> known;
  for (const ir::StateVar& s : r.states) known.insert(s.var);
  known.insert(r.algebraic.begin(), r.algebraic.end());
  for (int d : r.derivative_unknowns)
    if (d >= 0) known.insert(d);
  for (const ir::Assignment& a : r.assignments) {
    std::unordered_set<int> vars;
    ir::collect_vars(a.value, vars);
    for (int v : vars)
      EXPECT_TRUE(known.count(v)) << r.graph.vars[static_cast<std::size_t>(a.var)].name << " reads "
                                  << r.graph.vars[static_cast<std::size_t>(v)].name << " before it is computed";
    EXPECT_TRUE(known.insert(a.var).second) << "assigned twice: " << r.graph.vars[static_cast<std::size_t>(a.var)].name;
  }
  auto check_roots = [&](const ir::Expr& e, const std::string& what) {
    std::unordered_set<int> vars;
    ir::collect_vars(e, vars);
    for (int v : vars) EXPECT_TRUE(known.count(v)) << what << " reads " << r.graph.vars[static_cast<std::size_t>(v)].name;
  };
  for (const ir::Expr& e : r.state_derivative) check_roots(e, "a state derivative");
  for (const ir::Residual& res : r.residuals) check_roots(res.value, "a residual");
  for (const ir::Output& o : r.graph.outputs) check_roots(o.value, "output " + o.name);
  // The slices index the assignments in order and cover all of them.
  std::set<int> covered(r.for_derivative.begin(), r.for_derivative.end());
  covered.insert(r.for_outputs.begin(), r.for_outputs.end());
  covered.insert(r.for_energy.begin(), r.for_energy.end());  // (the energy witness's)
  covered.insert(r.for_power.begin(), r.for_power.end());
  EXPECT_EQ(covered.size(), r.assignments.size());
  EXPECT_TRUE(std::is_sorted(r.for_derivative.begin(), r.for_derivative.end()));
  EXPECT_TRUE(std::is_sorted(r.for_outputs.begin(), r.for_outputs.end()));
  EXPECT_FALSE(any_der(r));
  EXPECT_EQ(r.state_derivative.size(), r.states.size());
}

INSTANTIATE_TEST_SUITE_P(
    Reduce, ReduceInvariants,
    ::testing::Values(kSeriesRlc, kAlgebraicLoop, kTwoInertias, kNonlinearDae,
                      "Se g = [0, -9.81]\nI mass = diag(2, 2) { f0 = [1, 0] }\nC spring = diag(0.1, 0.1)\n"
                      "R damper = [[0.5, 0.1], [0.1, 0.5]]\n1 v : g -> mass, spring, damper\noutput vel = mass.f\n",
                      "Se grav = 9.81\nI m { f = p / 2 }\nR drag { e = 0.1 * f * abs(f) }\nsignal theta = t * 0.5\n"
                      "MTF arm = cos(theta)\n1 j : grav -> m, drag, arm\n0 n : arm -> c\nC c { e = 100 * q + 10*q^3 }\n"
                      "output v = m.f\noutput x = c.q\n"));

}  // namespace

// A loop whose pivots depend on the state (a modulated transformer in it) is
// not eliminated symbolically — a pivot like cos(theta) could vanish — but
// handed to the run-time solver with partial pivoting; the result is still
// the pendulum's exact acceleration.
TEST(ReduceLoops, StateDependentPivotsGiveANumericBlock) {
  auto c = reduce(
      "param m = 1\nparam L = 1\nparam g = 9.81\nparam J = 0.01\n"
      "I hub = J\nC angle { e = 0 }\n1 omega : -> hub, angle, arm\n"
      "MTF arm = [[L*cos(angle.q)], [L*sin(angle.q)]]\nI bob = diag(m, m)\nSe gravity = [0, -m*g]\n"
      "1 v : arm, gravity -> bob\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.linear_blocks.size(), 1u);
  // the hub's and the bob's efforts and flows' rates, and the rate of the arm's modulus
  EXPECT_EQ(r.linear_blocks[0].unknowns.size(), 11u);
  for (double theta : {0.0, 0.3, 1.5707963267948966, 2.5}) {
    for (double p : {0.0, 0.7}) {
      Env env = evaluate(r, {{"hub.p", p}, {"angle.q", theta}});
      // (J + m L^2) omega' = -m g L sin(theta) (the centripetal force is along
      // the rod), and the hub's own momentum changes as d(J omega)/dt.
      const double J = 0.01, m = 1, L = 1, g = 9.81;
      double expected = J * (-m * g * L * std::sin(theta)) / (J + m * L * L);
      EXPECT_NEAR(eval(r.state_derivative[0], env), expected, 1e-12) << theta << " " << p;
    }
  }
}

// A free rate `Sf { rate0 }` makes its flow a state whose derivative follows
// from e = 0: the same pendulum with the hub's rate as the state and a
// massless hub. The bob's inertia takes derivative causality; reduce must
// give the angular acceleration -g sin(theta) / L, independent of the rate.
TEST(ReduceFreeRate, PendulumAccelerationFromZeroEffort) {
  auto c = reduce(
      "param m = 1\nparam L = 1\nparam g = 9.81\n"
      "Sf hub { rate0 = 0 }\nC angle { e = 0 }\n1 omega : hub -> angle, arm\n"
      "MTF arm = [[L*cos(angle.q)], [L*sin(angle.q)]]\nI bob = diag(m, m)\nSe gravity = [0, -m*g]\n"
      "1 v : arm, gravity -> bob\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  const ir::ReducedSystem& r = c->reduced;
  ASSERT_EQ(r.states.size(), 2u);  // hub.rate and angle.q
  EXPECT_FALSE(r.dae);
  std::size_t rate = r.graph.vars[static_cast<std::size_t>(r.states[0].var)].name == "hub.rate" ? 0 : 1;
  for (double theta : {0.0, 0.3, 1.5707963267948966, 2.5})
    for (double w : {0.0, 0.7}) {
      Env env = evaluate(r, {{"hub.rate", w}, {"angle.q", theta}});
      EXPECT_NEAR(eval(r.state_derivative[rate], env), -9.81 * std::sin(theta), 1e-12) << theta << " " << w;
      EXPECT_NEAR(eval(r.state_derivative[1 - rate], env), w, 1e-15);
    }
}

// The symbolic Jacobian handed to CVODE equals central finite differences of
// the reduced state derivatives, on linear, nonlinear, modulated, multibond
// and derivative-causality models.
TEST(ReduceJacobian, MatchesFiniteDifferencesOfTheStateDerivatives) {
  const char* models[] = {
      // DC motor (linear, two domains)
      "Se s = 60\nR r = 0.4\nI l = 0.05\nGY k = 0.678\nI j = 0.57207\nR d = 0.226\n1 a : s -> r, l, k\n1 b : k -> j, d\n",
      // nonlinear laws and a modulated transformer driven by a state
      "Se g = 9.81\nI m { f = p / 2 }\nR drag { e = 0.1 * f * abs(f) }\nMTF arm = cos(c.q)\n1 j : g -> m, drag, arm\n"
      "0 n : arm -> c\nC c { e = 100 * q + 10 * q^3 }\n",
      // 2-dimensional multibond with coupled matrices
      "Se w = [0, -19.62]\nI mass = diag(2, 2)\nC spring = diag(0.1, 0.1)\nR damper = [[0.5, 0.1], [0.1, 0.5]]\n"
      "1 v : w -> mass, spring, damper\n",
      // derivative causality through a gear, with a spring
      "Se F = 2\nI a = 1\nTF g = 2\nI b = 3\nC k = 0.5\n1 j1 : F -> a, g\n1 j2 : g -> b, k\n",
  };
  for (const char* text : models) {
    auto c = reduce(text);
    ASSERT_TRUE(c->ok()) << c->messages();
    const ir::ReducedSystem& r = c->reduced;
    std::size_t n = r.states.size();
    ASSERT_EQ(r.jacobian.size(), n * n) << text;
    std::map<std::string, double> x;
    for (std::size_t j = 0; j < n; ++j) x[r.graph.vars[static_cast<std::size_t>(r.states[j].var)].name] = 0.3 + 0.2 * j;
    Env at = evaluate(r, x, 0.5);
    for (std::size_t j = 0; j < n; ++j) {
      const std::string name = r.graph.vars[static_cast<std::size_t>(r.states[j].var)].name;
      const double h = 1e-6;
      auto plus = x, minus = x;
      plus[name] += h;
      minus[name] -= h;
      Env ep = evaluate(r, plus, 0.5), em = evaluate(r, minus, 0.5);
      for (std::size_t i = 0; i < n; ++i) {
        double fd = (eval(r.state_derivative[i], ep) - eval(r.state_derivative[i], em)) / (2 * h);
        double sym = eval(r.jacobian[i * n + j], at);
        EXPECT_NEAR(sym, fd, 1e-6 * std::max(1.0, std::abs(fd))) << text << "\nentry " << i << "," << j;
      }
    }
  }
}

TEST(ReduceJacobian, NoneWhenALoopIsSolvedAtRunTime) {
  auto c = reduce(
      "I hub = 0.01\nC angle { e = 0 }\n1 omega : -> hub, angle, arm\n"
      "MTF arm = [[cos(angle.q)], [sin(angle.q)]]\nI bob = diag(1, 1)\nSe gravity = [0, -9.81]\n"
      "1 v : arm, gravity -> bob\n");
  ASSERT_TRUE(c->ok()) << c->messages();
  EXPECT_FALSE(c->reduced.linear_blocks.empty());
  EXPECT_TRUE(c->reduced.jacobian.empty());
}
