// Every integrator against closed forms. Tolerances are stated per case and
// chosen from the method's expected accuracy, not from what happened to pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

struct Case {
  std::string solver;
  std::vector<std::string> args;  ///< accuracy settings for this solver
  double tol;                     ///< max |error| allowed against the closed form
};

// rk4, h = 1e-3: global error ~ (omega h)^4 omega t / 120 ~ 1e-11 at most here
// (measured 2e-12). Adaptive solvers at rtol 1e-10: the global error grows with
// the number of periods; measured on the 10 s oscillator: dopri5 1e-10, cvode
// and ida 1.6e-8. The limits leave a 5-100x margin while still catching a
// wrong table, a lost step or a wrong order (which cost several digits).
const std::vector<Case> kCases = {
    {"rk4", {"--step", "1e-3"}, 1e-10},
    {"dopri5", {"--rtol", "1e-10", "--atol", "1e-12"}, 1e-8},
    {"cvode", {"--rtol", "1e-10", "--atol", "1e-12"}, 1e-7},
    {"ida", {"--rtol", "1e-10", "--atol", "1e-12"}, 1e-7},
};

std::vector<std::string> with_solver(const Case& c, std::vector<std::string> extra = {}) {
  std::vector<std::string> args{"--solver", c.solver};
  args.insert(args.end(), c.args.begin(), c.args.end());
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.solver; }

class EachSolver : public ::testing::TestWithParam<Case> {};

TEST_P(EachSolver, ExponentialDecayMatchesClosedForm) {
  const Case& c = GetParam();
  Decay m;
  RunResult r = run(m, with_solver(c));
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 21u);
  for (const auto& row : csv.rows) EXPECT_NEAR(row[1], m.exact(row[0]), c.tol) << "t = " << row[0];
}

TEST_P(EachSolver, HarmonicOscillatorAtTenSeconds) {
  const Case& c = GetParam();
  const double omega = 2.0;
  Oscillator m(omega);
  RunResult r = run(m, with_solver(c));
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 101u);
  const std::size_t last = csv.rows.size() - 1;
  EXPECT_EQ(csv.at(last, "t"), 10.0);
  EXPECT_NEAR(csv.at(last, "x"), std::cos(omega * 10.0), c.tol);
  EXPECT_NEAR(csv.at(last, "v"), -omega * std::sin(omega * 10.0), c.tol);
  // Energy 0.5 v^2 + 0.5 omega^2 x^2 = 2 J must be conserved along the whole run.
  // With |v| <= 2 and omega^2 |x| <= 4, state errors of tol move it by at most 6 tol.
  double drift = 0.0;
  for (std::size_t i = 0; i < csv.rows.size(); ++i)
    drift = std::max(drift, std::abs(csv.at(i, "energy") - 2.0));
  EXPECT_LT(drift, 6.0 * c.tol) << "energy drift";
}

INSTANTIATE_TEST_SUITE_P(Solvers, EachSolver, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return info.param.solver; });

double rk4_error_at_two_seconds(double step) {
  Decay m;
  RunResult r = run(m, {"--solver", "rk4", "--step", std::to_string(step), "--interval", "0.5"});
  EXPECT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  return std::abs(csv.rows.back()[1] - m.exact(2.0));
}

TEST(Rk4, ErrorFallsWithTheFourthPowerOfTheStep) {
  // Both steps divide the 0.5 s interval, so halving --step halves the actual step.
  const double coarse = rk4_error_at_two_seconds(0.25), fine = rk4_error_at_two_seconds(0.125);
  ASSERT_GT(fine, 1e-12) << "errors must stay above rounding for the ratio to mean anything";
  EXPECT_NEAR(coarse / fine, 16.0, 2.0);
}

TEST(Rk4, StepDefaultsToATenthOfTheInterval) {
  Decay m;
  RunResult r = run(m, {"--solver", "rk4"});
  ASSERT_EQ(r.status, 0);
  EXPECT_TRUE(Contains(r.err, "steps        200 ")) << "2 s at 0.01 s";
}

long steps_at(const char* solver, const char* rtol) {
  Oscillator m;
  RunResult r = run(m, {"--solver", solver, "--rtol", rtol, "--atol", "1e-14"});
  EXPECT_EQ(r.status, 0) << r.err;
  return summary_number(r.err, "steps");
}

TEST(Dopri5, StepCountScalesLikeAFifthOrderMethod) {
  // Error-per-step control with a 4th-order embedded estimate gives h ~ tol^(1/5):
  // 1e5 tighter tolerance -> about 10x the steps. A 3(2) pair would need ~46x.
  const long loose = steps_at("dopri5", "1e-5"), tight = steps_at("dopri5", "1e-10");
  ASSERT_GT(loose, 0);
  const double ratio = static_cast<double>(tight) / static_cast<double>(loose);
  EXPECT_GT(ratio, 6.0);
  EXPECT_LT(ratio, 16.0);
}

TEST(Cvode, ErrorShrinksUnderToleranceRefinement) {
  auto error = [](const char* rtol) {
    Oscillator m;
    RunResult r = run(m, {"--solver", "cvode", "--rtol", rtol, "--atol", "1e-14"});
    EXPECT_EQ(r.status, 0) << r.err;
    return std::abs(parse_csv(r.csv).rows.back()[1] - std::cos(20.0));
  };
  const double loose = error("1e-5"), tight = error("1e-8");
  EXPECT_LT(tight, loose / 50) << "loose " << loose << " tight " << tight;
}

TEST(Ida, SmallIndexOneDaeMatchesClosedForm) {
  SmallDae m;
  RunResult r = run(m, {});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 21u);
  // The first row must already be consistent: IDACalcIC corrected z(0) = 0 to -2.
  EXPECT_NEAR(csv.at(0, "z"), -2.0, 1e-9);
  EXPECT_NEAR(csv.at(0, "xdot"), -3.0, 1e-6);
  // rtol 1e-9: 1e-7 absolute on values of order one.
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    const double t = csv.at(i, "t"), x = std::exp(-3.0 * t);
    EXPECT_NEAR(csv.at(i, "x"), x, 1e-7) << "t = " << t;
    EXPECT_NEAR(csv.at(i, "z"), -2.0 * x, 2e-7) << "t = " << t;
    EXPECT_NEAR(csv.at(i, "xdot"), -3.0 * x, 1e-6) << "t = " << t;  // y' is one order less accurate
  }
  EXPECT_TRUE(Contains(r.err, "residual"));
}

TEST(Ida, ZeroLengthDaeRunStillWritesConsistentValues) {
  SmallDae m;
  RunResult r = run(m, {"--t-end", "0"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_NEAR(csv.at(0, "z"), -2.0, 1e-9);
}

TEST(Ida, DaeParametersAreHonoured) {
  SmallDae m;
  RunResult r = run(m, {"--set", "x0=2"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  EXPECT_NEAR(csv.rows.back()[1], 2.0 * std::exp(-3.0), 2e-7);
}

TEST(Terminal, IsCalledOnceAtTheEnd) {
  Decay m;
  RunResult r = run(m, {});
  ASSERT_EQ(r.status, 0);
  EXPECT_EQ(m.terminal_calls, 1);
  EXPECT_EQ(m.terminal_t, 2.0);
}

}  // namespace
}  // namespace mbgrt::test

namespace mbgrt::test {
namespace {

/// The oscillator with its Jacobian, as mbgc generates one for ODEs.
class OscillatorWithJacobian : public Oscillator {
 public:
  OscillatorWithJacobian() : Oscillator(2.0, 0.1) {}
  bool has_jacobian() const override { return true; }
  void jacobian(double, const double*, double* J) override {
    const double w = p("omega"), z = p("zeta");
    J[0] = 0, J[1] = 1, J[2] = -w * w, J[3] = -2 * z * w;
  }
};

TEST(Jacobian, CvodeUsesTheModelsJacobianUnlessToldToUseFiniteDifferences) {
  OscillatorWithJacobian generated, fd;
  RunResult a = run(generated, {"--solver", "cvode", "--rtol", "1e-9", "--atol", "1e-11"});
  RunResult b = run(fd, {"--solver", "cvode", "--rtol", "1e-9", "--atol", "1e-11", "--fd-jacobian"});
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_TRUE(Contains(a.err, "generated")) << a.err;
  EXPECT_TRUE(Contains(b.err, "finite-difference")) << b.err;
  EXPECT_TRUE(Contains(a.err, "(+ 0 for finite-difference Jacobians)")) << a.err;
  EXPECT_TRUE(Contains(b.err, "for finite-difference Jacobians")) << b.err;
  EXPECT_FALSE(Contains(b.err, "(+ 0 for finite-difference Jacobians)")) << b.err;
  // the same solution either way, to the tolerance
  const Csv ca = parse_csv(a.csv), cb = parse_csv(b.csv);
  ASSERT_EQ(ca.rows.size(), cb.rows.size());
  for (std::size_t i = 0; i < ca.rows.size(); ++i) EXPECT_NEAR(ca.rows[i][1], cb.rows[i][1], 1e-7);
}

}  // namespace
}  // namespace mbgrt::test
