// Divergence handling: a run that goes non-finite must stop with exit status
// 1, keep the rows it wrote, and say at what time which state failed and why.
#include <gtest/gtest.h>

#include <cmath>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

struct FailCase {
  std::string solver;
  std::string flag_prefix;  ///< the solver's own flag names start with this
};

void PrintTo(const FailCase& c, std::ostream* os) { *os << c.solver; }

class NanDerivative : public ::testing::TestWithParam<FailCase> {};

TEST_P(NanDerivative, StopsNamesStateAndTimeAndKeepsRows) {
  const FailCase& c = GetParam();
  DrainingTank m;
  RunResult r = run(m, {"--solver", c.solver});
  EXPECT_EQ(r.status, 1);

  // level' = sqrt(1 - t) is finite up to t = 1, so the first NaN is seen just after it.
  EXPECT_TRUE(Contains(r.err, "mbgrt: error: at t = "));
  EXPECT_TRUE(Contains(r.err, "state 'tank.level' became NaN (derivative non-finite)"));
  EXPECT_TRUE(Contains(r.err, "solver " + c.solver + " stopped: " + c.flag_prefix));
  const double t_fail = reported_time(r.err);
  EXPECT_GT(t_fail, 1.0);
  EXPECT_LE(t_fail, 2.0);

  // Rows before the failure are kept and are right. Step-size control near the
  // singular slope at t = 1 may stop a solver before the t = 1 row, never before 0.8.
  Csv csv = parse_csv(r.csv);
  ASSERT_GE(csv.rows.size(), 9u);
  for (const auto& row : csv.rows) {
    EXPECT_LE(row[0], 1.0);
    EXPECT_NEAR(row[1], DrainingTank::exact(row[0]), 1e-4) << "t = " << row[0];
  }
  // SUNDIALS must not print on its own: its message is quoted in our report instead.
  EXPECT_EQ(r.err.find("[CVODE"), std::string::npos);
  EXPECT_EQ(r.err.find("[ARKODE"), std::string::npos);
  EXPECT_EQ(r.err.find("[IDA"), std::string::npos);
  EXPECT_EQ(m.terminal_calls, 1);
  EXPECT_LE(m.terminal_t, 1.0);
}

INSTANTIATE_TEST_SUITE_P(Solvers, NanDerivative,
                         ::testing::Values(FailCase{"rk4", "RK4_NONFINITE"},
                                           FailCase{"dopri5", "ARK_"}, FailCase{"cvode", "CV_"},
                                           FailCase{"ida", "IDA_"}),
                         [](const auto& info) { return info.param.solver; });

TEST(Failure, CvodeReportsRhsFailureInPlainEnglish) {
  DrainingTank m;
  RunResult r = run(m, {"--solver", "cvode"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err,
                       "CV_RHSFUNC_FAIL (the right-hand side function failed in an "
                       "unrecoverable manner)"));
  EXPECT_TRUE(Contains(r.err, "mbgrt: note: solver message:"));
}

TEST(Failure, BlowUpIsCaughtByAdaptiveSolverNearTheSingularity) {
  BlowUp m;  // x = 1 / (1 - t)
  RunResult r = run(m, {"--solver", "cvode", "--rtol", "1e-10", "--atol", "1e-12"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "solver cvode stopped: CV_"));
  const double t = reported_time(r.err);
  EXPECT_GT(t, 0.9);
  EXPECT_LE(t, 1.0 + 1e-9);
  Csv csv = parse_csv(r.csv);
  ASSERT_GE(csv.rows.size(), 9u);
  // Error is amplified like x^2 on this solution; 1e-6 relative at rtol 1e-10 leaves margin.
  for (const auto& row : csv.rows) EXPECT_NEAR(row[1], 1.0 / (1.0 - row[0]), 1e-6 * row[1]);
}

TEST(Failure, BlowUpUnderRk4NamesTheState) {
  BlowUp m;
  RunResult r = run(m, {"--solver", "rk4", "--step", "1e-3"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "state 'x' became"));
  EXPECT_TRUE(Contains(r.err, "RK4_NONFINITE"));
  EXPECT_GT(reported_time(r.err), 0.99);
}

TEST(Failure, ModelExceptionIsReportedNotPropagated) {
  Throwing m;  // throws for t > 0.5
  RunResult r = run(m, {"--solver", "rk4", "--step", "0.01"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "the model threw an exception: table lookup out of range"));
  // rk4 evaluates no later than t = 0.5 until the step that starts there.
  EXPECT_EQ(parse_csv(r.csv).rows.size(), 6u);

  Throwing m2;
  RunResult r2 = run(m2, {"--solver", "cvode"});
  EXPECT_EQ(r2.status, 1);
  EXPECT_TRUE(Contains(r2.err, "table lookup out of range"));
}

TEST(Failure, StiffModelUnderAnExplicitSolverStopsWithAdvice) {
  Stiff m;
  RunResult r = run(m, {"--solver", "dopri5"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "solver dopri5 stopped: ARK_TOO_MUCH_WORK"));
  EXPECT_TRUE(Contains(r.err, "try --solver cvode"));
  EXPECT_EQ(parse_csv(r.csv).rows.size(), 1u) << "only t = 0 is reached";
}

TEST(Failure, StiffModelUnderCvodeFollowsTheSlowSolution) {
  Stiff m;
  RunResult r = run(m, {"--solver", "cvode", "--rtol", "1e-8", "--atol", "1e-10"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  // After the 1 us transient, x = cos t + sin(t) / lambda + O(1/lambda^2).
  for (std::size_t i = 1; i < csv.rows.size(); ++i) {
    const double t = csv.rows[i][0];
    EXPECT_NEAR(csv.rows[i][1], std::cos(t) + std::sin(t) * 1e-6, 1e-8) << "t = " << t;
  }
}

TEST(Failure, QuietStillPrintsTheStopMessage) {
  DrainingTank m;
  RunResult r = run(m, {"--solver", "cvode", "--quiet"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "mbgrt: error: at t = "));
  EXPECT_EQ(r.err.find("run summary"), std::string::npos);
}

}  // namespace
}  // namespace mbgrt::test
