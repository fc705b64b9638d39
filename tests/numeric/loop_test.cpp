// loop_test.cpp — closed loops at their limits (models/slider_crank.mbg, a
// slider-crank driven at 10 rad/s): through its dead centres it follows the
// closed form under every strategy; with a rod shorter than the crank the
// loop cannot close a quarter of a turn in, and every strategy must stop
// there with a report and exit status 1, never write rows of a broken
// mechanism with exit status 0. And IFToMM's N four-bar
// (models/n_four_bar.mbg): a row of parallelograms whose loops' rows become
// dependent twice a turn, against its exact one-degree-of-freedom motion.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// The run summary's energy balance: its largest residual (J); +inf if absent.
double energy_residual(const SimRun& r) {
  const std::size_t at = r.log.find("energy       residual ");
  return at == std::string::npos ? HUGE_VAL : std::stod(r.log.substr(at + 22));
}

double worst_error(const SimRun& r) {
  double worst = 0.0;
  for (const auto& row : r.csv.rows) worst = std::max(worst, std::abs(row[r.csv.col("x")] - row[r.csv.col("x_exact")]));
  return worst;
}

struct Strategy {
  const char* name;
  const char* sim;
  double tolerance;  ///< of x against the closed form (m)
};

class SliderCrank : public ::testing::TestWithParam<Strategy> {};

}  // namespace

TEST_P(SliderCrank, RunsThroughItsDeadCentresAsTheClosedFormSays) {
  const Strategy& s = GetParam();
  SimRun r = run(s.sim, "", std::string("slider_crank_") + s.name);
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 201u) << r.log;  // 2 s: three turns, six dead centres
  EXPECT_LT(worst_error(r), s.tolerance) << r.log;
}

/// The rod (0.1 m) reaches the axis only while 0.2 sin(10 t) <= 0.1: up to
/// t = asin(0.5) / 10 = 0.05236 s, the dead point where it is perpendicular
/// to the axis. The run must stop soon after, naming the joint that opens.
TEST_P(SliderCrank, WithARodShorterThanTheCrankStopsWhereTheLoopCannotClose) {
  const Strategy& s = GetParam();
  SimRun r = run(s.sim, "--set L=0.1", std::string("slider_crank_short_") + s.name);
  EXPECT_EQ(r.status, 1) << r.log;
  EXPECT_TRUE(contains(r.log, "mbgrt: error: at t = ")) << r.log;
  ASSERT_FALSE(r.csv.rows.empty()) << r.log;
  const double last = r.csv.rows.back()[0];
  EXPECT_GT(last, 0.04) << r.log;  // it ran up to the dead point
  EXPECT_LT(last, 0.2) << r.log;   // and stopped soon after it
  for (const auto& row : r.csv.rows)
    for (double v : row) ASSERT_TRUE(std::isfinite(v)) << "t = " << row[0];
  if (std::string(s.name) == "coordinates") {
    EXPECT_TRUE(contains(r.log, "joint row j3.cn[")) << r.log;
    EXPECT_TRUE(contains(r.log, "a loop that cannot close")) << r.log;
    EXPECT_TRUE(contains(r.log, "the cut joints' rows first became dependent at t = 0.0523")) << r.log;
  } else if (std::string(s.name) == "penalty") {
    EXPECT_TRUE(contains(r.log, "penalty joint row")) << r.log;
  } else {
    EXPECT_TRUE(contains(r.log, "the joints' constraint rows are close to losing rank")) << r.log;
  }
}

/// Started where the loop cannot close (the crank at 90 degrees), nothing runs.
TEST_P(SliderCrank, StartedWhereTheLoopCannotCloseAssemblyFails) {
  const Strategy& s = GetParam();
  SimRun r = run(s.sim, "--set L=0.1 --set th0=1.5708", std::string("slider_crank_start_") + s.name);
  EXPECT_EQ(r.status, 1) << r.log;
  EXPECT_TRUE(contains(r.log, "assembly failed: constraint `j")) << r.log;
  EXPECT_TRUE(contains(r.log, "the joints cannot all be closed")) << r.log;
  EXPECT_TRUE(r.csv.rows.empty()) << r.log;
}

INSTANTIATE_TEST_SUITE_P(Strategies, SliderCrank,
                         ::testing::Values(Strategy{"coordinates", SLIDER_CRANK_SIM, 1e-7},
                                           // a penalty joint gives F / k (the driven crank's row
                                           // lags by 8.8e-5 rad): measured 3.7e-4 m
                                           Strategy{"penalty", SLIDER_CRANK_PENALTY_SIM, 1e-3},
                                           Strategy{"lagrange", SLIDER_CRANK_LAGRANGE_SIM, 1e-7}),
                         [](const ::testing::TestParamInfo<Strategy>& info) { return std::string(info.param.name); });

// ---- IFToMM's N four-bar through its aligned configurations ----

namespace {

/// The exact motion of the row: every crank at theta, I theta'' = -k cos theta
/// (cranks about their pivots, couplers translating with the crank tips),
/// integrated with classical RK4 at 1e-4 s (error below 1e-12 rad over 10 s).
/// Returns the last coupler's end, (N + cos theta, sin theta) L, at each row's
/// time; rows are on a 0.01 s grid.
double worst_tip_error(const SimRun& r, int n, double th0 = M_PI / 2) {
  const double m = 1, L = 1, g = 9.81;
  const double inertia = m * L * L * ((n + 1) / 3.0 + n), k = g * m * L * ((n + 1) / 2.0 + n);
  const auto rate = [&](double th, double w, double& dth, double& dw) { dth = w, dw = -k * std::cos(th) / inertia; };
  double th = th0, w = 2.0, worst = 0.0;
  const double dt = 1e-4;
  long done = 0;
  for (const auto& row : r.csv.rows) {
    for (const long target = std::lround(row[0] / dt); done < target; ++done) {
      double a1, b1, a2, b2, a3, b3, a4, b4;
      rate(th, w, a1, b1);
      rate(th + dt / 2 * a1, w + dt / 2 * b1, a2, b2);
      rate(th + dt / 2 * a2, w + dt / 2 * b2, a3, b3);
      rate(th + dt * a3, w + dt * b3, a4, b4);
      th += dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
      w += dt / 6 * (b1 + 2 * b2 + 2 * b3 + b4);
    }
    worst = std::max(worst, std::hypot(row[r.csv.col("x")] - (n + std::cos(th)) * L,
                                       row[r.csv.col("y")] - std::sin(th) * L));
  }
  return worst;
}

struct Row {
  int n;
  const char* sim;
};

class NFourBar : public ::testing::TestWithParam<Row> {};

}  // namespace

namespace {

/// Runs the row with `options`: 10 s written, within 1e-6 m of the exact motion.
SimRun expect_exact_motion(const Row& row, const std::string& options, const std::string& name) {
  SimRun r = run(row.sim, options, name + std::to_string(row.n));
  EXPECT_EQ(r.status, 0) << r.log;
  EXPECT_EQ(r.csv.rows.size(), 1001u) << r.log;
  if (!r.csv.rows.empty()) EXPECT_LT(worst_tip_error(r, row.n), 1e-6) << r.log;
  return r;
}

}  // namespace

/// The model's own settings: dopri5 at rtol 1e-8, 10 s, 13 aligned passages
/// for every crank. Measured: 1.1e-8 m (N = 4) and 1.05e-8 m (N = 10), the
/// CSV's nine digits.
TEST_P(NFourBar, RunsTenSecondsThroughItsAlignedConfigurationsAsTheExactModel) {
  SimRun r = expect_exact_motion(GetParam(), "", "n_four_bar_");
  EXPECT_FALSE(contains(r.log, "mbgrt: warning")) << r.log;
}

/// RK4 at 1 ms: 2.8e-10 m (N = 4) measured.
TEST_P(NFourBar, RunsThroughWithRk4) { expect_exact_motion(GetParam(), "--solver rk4 --step 0.001", "n_four_bar_rk4_"); }

/// A tighter tolerance must not stop a run that passes at a looser one. The
/// cut joints' rows drift by some 5e-10 m through each aligned passage at
/// rtol 1e-11 to 1e-13 alike (rounding, where the rows are dependent); the
/// bound on a row that must hold once followed the tolerances down to
/// 1e-10 m and stopped these runs at t = 1.05 s (dopri5) and 2.56 s (cvode)
/// at rtol 1e-13 (N = 4); it is now never tighter than at rtol 1e-9.
/// Measured over 10 s: 3.3e-7 / 3.0e-7 m (N = 4), 6.2e-8 / 7.2e-8 m
/// (N = 10).
TEST_P(NFourBar, AtRtol1e13ExplicitAndImplicitRunsGoThroughTheAlignedPassages) {
  for (const char* solver : {"dopri5", "cvode"})
    expect_exact_motion(GetParam(), std::string("--solver ") + solver + " --rtol 1e-13 --atol 1e-15",
                        std::string("n_four_bar_tight_") + solver + "_");
}

/// Started aligned (the cranks horizontal), the multipliers' rows are
/// dependent from t = 0: the run still follows the exact model (measured
/// 3.4e-8 m, N = 4), and its summary lists each stretch of time the rows
/// were dependent and which (measured: 4 for N = 4, the first from t = 0).
TEST_P(NFourBar, StartedAlignedTheSummaryNamesTheRowsAndWhenTheyWereDependent) {
  const Row& row = GetParam();
  SimRun r = run(row.sim, "--set th0=0", "n_four_bar_aligned_" + std::to_string(row.n));
  ASSERT_EQ(r.status, 0) << r.log;
  EXPECT_LT(worst_tip_error(r, row.n, 0.0), 1e-6) << r.log;
  EXPECT_TRUE(contains(r.log, "dependent rows: ")) << r.log;
  EXPECT_TRUE(contains(r.log, " episodes (rows dependent within 0.001 s of each other):")) << r.log;
  EXPECT_TRUE(contains(r.log, "               t = 0 to ")) << r.log;
  const std::string first = "q" + std::to_string(row.n) + ".cn.e[1]";  // the last loop's row along the links
  EXPECT_TRUE(contains(r.log, "rank " + std::to_string(row.n) + " of " + std::to_string(2 * row.n) + ", ")) << r.log;
  EXPECT_TRUE(contains(r.log, first)) << r.log;
}

/// CVODE's BDF across the aligned configurations could carry the row off its
/// branch without failing a test (measured before the hand-over, at rtol
/// 1e-8 over 10 s: N = 4 0.020 m off, N = 1 on the other branch). An
/// implicit method watches the cut joints' independence and hands each
/// aligned passage to dopri5 at the same tolerances
/// (solvers/carry_across.hpp); the summary lists the spans and nothing is
/// warned. The error is then the method's own, falling with the tolerance:
/// measured for CVODE 6.8e-5 m (N = 4) and 1.5e-4 m (N = 10) at rtol 1e-8,
/// 3.1e-7 and 3.3e-7 m at rtol 1e-11; IDA on the same ODE 8.5e-5 and 9.2e-5
/// m at rtol 1e-8.
TEST_P(NFourBar, AnImplicitMethodHandsEachAlignedPassageToAnExplicitOneAndKeepsToTheBranch) {
  const Row& row = GetParam();
  const std::string spans = "across 13 change points of the cut joints, where their rows became dependent, dopri5 "
                            "carried the run at the same tolerances: t = 0.4";
  for (const std::string solver : {"cvode", "ida"}) {
    SimRun loose = run(row.sim, "--solver " + solver, "n_four_bar_" + solver + "_" + std::to_string(row.n));
    ASSERT_EQ(loose.status, 0) << loose.log;
    EXPECT_LT(worst_tip_error(loose, row.n), 1e-3) << loose.log;  // the other branch is metres away
    EXPECT_FALSE(contains(loose.log, "mbgrt: warning")) << loose.log;
    EXPECT_TRUE(contains(loose.log, spans)) << loose.log;
  }
  SimRun tight = run(row.sim, "--solver cvode --rtol 1e-11 --atol 1e-13", "n_four_bar_cvode_tight_" + std::to_string(row.n));
  ASSERT_EQ(tight.status, 0) << tight.log;
  EXPECT_LT(worst_tip_error(tight, row.n), 1e-6) << tight.log;
  // a run that ends while dopri5 carries it (the first passage: 0.49 to 0.61 s)
  SimRun inside = run(row.sim, "--solver cvode --t-end 0.55", "n_four_bar_cvode_inside_" + std::to_string(row.n));
  ASSERT_EQ(inside.status, 0) << inside.log;
  EXPECT_FALSE(contains(inside.log, "mbgrt: warning")) << inside.log;
  EXPECT_TRUE(contains(inside.log, "; across 1 change point of the cut joints")) << inside.log;
}

/// Started aligned (the cranks horizontal) the cut joints are dependent from
/// t = 0, so there is no independence to watch: an implicit method near the
/// aligned configurations is then warned, on stderr and naming the remedy,
/// not only in its summary; under --strict that is an error.
TEST_P(NFourBar, AnImplicitMultistepRunNearTheAlignedConfigurationsIsWarnedAbout) {
  const Row& row = GetParam();
  SimRun r = run(row.sim, "--solver cvode --set th0=0 --t-end 2 --quiet", "n_four_bar_cvode_aligned_" + std::to_string(row.n));
  EXPECT_TRUE(contains(r.log, "mbgrt: warning: cvode integrated ")) << r.log;
  EXPECT_TRUE(contains(r.log, "a configuration where the cut joints' rows become dependent") ||
              contains(r.log, "where the cut joints' rows were dependent"))
      << r.log;
  EXPECT_TRUE(contains(r.log, "an explicit method steps across (--solver dopri5, or rk4)")) << r.log;
  // a warning: the rows are written, exit status 0; under --strict an error
  EXPECT_EQ(r.status, 0) << r.log;
  SimRun strict = run(row.sim, "--solver cvode --set th0=0 --t-end 2 --quiet --strict",
                      "n_four_bar_cvode_aligned_strict_" + std::to_string(row.n));
  EXPECT_EQ(strict.status, 1) << strict.log;
  EXPECT_TRUE(contains(strict.log, "mbgrt: error: cvode integrated ")) << strict.log;
  EXPECT_TRUE(contains(strict.log, " (--strict)")) << strict.log;
}

INSTANTIATE_TEST_SUITE_P(Rows, NFourBar,
                         ::testing::Values(Row{4, N_FOUR_BAR_4_SIM}, Row{10, N_FOUR_BAR_10_SIM}),
                         [](const ::testing::TestParamInfo<Row>& info) { return "N" + std::to_string(info.param.n); });

// ---- the same rows with multipliers (a DAE under IDA) ----

namespace {

class NFourBarMultipliers : public ::testing::TestWithParam<Row> {};

}  // namespace

/// IDA cannot converge where the rows become dependent; it steps across each
/// aligned passage instead (solvers/change_point.hpp) and restarts beyond.
/// At rtol 1e-10 (IDA's own drift at the model's 1e-8 is 1e-4 m over 10 s,
/// aligned passages or not) measured: N = 1, 10 s, 13 passages, 3.4e-7 m;
/// N = 4, 3 s, 4 passages, 1.1e-7 m; N = 10 (583 unknowns: the rates of a
/// step's stages are solved on the residual's sparsity pattern), 3 s, 4
/// passages, 7.3e-8 m. A step across must not cost energy: the summary's
/// balance stays below 1e-5 J of the 20 J (N = 1) to 331 J (N = 10) in play.
TEST_P(NFourBarMultipliers, StepsAcrossItsAlignedConfigurationsAsTheExactModel) {
  const Row& row = GetParam();
  const double t_end = row.n == 1 ? 10.0 : 3.0;
  SimRun r = run(row.sim, "--t-end " + std::to_string(t_end) + " --rtol 1e-10 --atol 1e-12", "n_four_bar_lagrange_" + std::to_string(row.n));
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), static_cast<std::size_t>(std::lround(t_end / 0.01)) + 1) << r.log;
  EXPECT_LT(worst_tip_error(r, row.n), 1e-6) << r.log;
  // every aligned passage stepped across (13 in 10 s, 4 in 3 s), one
  // sometimes in two steps (IDA failed again just beyond the first)
  const std::size_t across = r.log.find("stepped across ");
  ASSERT_NE(across, std::string::npos) << r.log;
  const int passages = row.n == 1 ? 13 : 4, steps = std::stoi(r.log.substr(across + 15));
  EXPECT_GE(steps, passages) << r.log;
  EXPECT_LE(steps, 2 * passages) << r.log;
  // the first ones listed with when and the row that lost its independence
  // (measured: q1.cn[1], the loop-closing pin's)
  EXPECT_TRUE(contains(r.log, "solvers/change_point.hpp): t = 0.5")) << r.log;
  EXPECT_TRUE(contains(r.log, "' the least independent row)")) << r.log;
  EXPECT_LT(energy_residual(r), 1e-5) << r.log;
}

/// A run that ends inside a passage ends with the steps across it: at
/// t_end = 1.02 s the second passage's steps reach past the run's end, and
/// were refused for that (IDA then stopped at t = 1.016 s, IDA_CONV_FAIL,
/// while t_end = 1.04 s ran through); a run ending exactly where the steps
/// across end must not ask IDA for the point it restarted at (t_end =
/// 0.52 s: IDA_ILL_INPUT). Measured: 4.2e-9 and 2.9e-9 m.
TEST(NFourBarMultipliersEnd, ARunEndingInsideAPassageEndsWithTheStepsAcrossIt) {
  for (const char* t_end : {"1.02", "0.52"}) {
    SimRun r = run(N_FOUR_BAR_4_LAGRANGE_SIM, std::string("--t-end ") + t_end + " --rtol 1e-10 --atol 1e-12",
                   std::string("n_four_bar_lagrange_end_") + t_end);
    ASSERT_EQ(r.status, 0) << r.log;
    EXPECT_EQ(r.csv.rows.size(), static_cast<std::size_t>(std::lround(std::stod(t_end) / 0.01)) + 1) << r.log;
    EXPECT_TRUE(contains(r.log, std::string(" to ") + t_end + " s ('")) << r.log;  // the last step across, to the end
    EXPECT_LT(worst_tip_error(r, 4), 1e-6) << r.log;
  }
}

/// Tightening the tolerances must never turn a run that passes into one that
/// fails. At rtol 1e-12 the rows' rounding noise, amplified as they approach
/// alignment, defeats IDA's Newton iteration at every step size before the
/// change point's watch fires (measured: it stopped at t = 0.458 s, the
/// tolerances floored at rounding or not); rtol 1e-11 runs through. The run
/// goes on from there at tenfold looser tolerances, says so, and is at
/// least as accurate as the looser run (measured over 1 s: 1.4e-9 m at rtol
/// 1e-12, 4.2e-9 m at rtol 1e-10).
TEST(NFourBarMultipliersTight, ATolerancePastWhatTheArithmeticResolvesIsLoosenedWhereItFailsAndSaidSo) {
  const std::string horizon = "--t-end 1 ";
  SimRun tight = run(N_FOUR_BAR_4_LAGRANGE_SIM, horizon + "--rtol 1e-12 --atol 1e-14", "n_four_bar_lagrange_tight");
  ASSERT_EQ(tight.status, 0) << tight.log;
  ASSERT_EQ(tight.csv.rows.size(), 101u) << tight.log;
  EXPECT_TRUE(contains(tight.log, "note: the asked rtol 1e-12, atol 1e-14 are more than this model's arithmetic "
                                  "resolves from t = 0.4"))
      << tight.log;
  EXPECT_TRUE(contains(tight.log, "the run went on from there at rtol 1e-11, atol 1e-13")) << tight.log;
  SimRun loose = run(N_FOUR_BAR_4_LAGRANGE_SIM, horizon + "--rtol 1e-10 --atol 1e-12", "n_four_bar_lagrange_loose");
  ASSERT_EQ(loose.status, 0) << loose.log;
  EXPECT_FALSE(contains(loose.log, "the run went on from there")) << loose.log;
  EXPECT_LE(worst_tip_error(tight, 4), worst_tip_error(loose, 4)) << tight.log << loose.log;
  EXPECT_LT(worst_tip_error(tight, 4), 1e-8) << tight.log;
}

INSTANTIATE_TEST_SUITE_P(Rows, NFourBarMultipliers,
                         ::testing::Values(Row{1, N_FOUR_BAR_1_LAGRANGE_SIM}, Row{4, N_FOUR_BAR_4_LAGRANGE_SIM},
                                           Row{10, N_FOUR_BAR_10_LAGRANGE_SIM}),
                         [](const ::testing::TestParamInfo<Row>& info) { return "N" + std::to_string(info.param.n); });

// ---- Bricard's linkage: a loop whose rows are dependent throughout ----

/// Six revolute joints close one loop of six links (models/bricard.mbg):
/// Grübler's count gives 0 degrees of freedom, the geometry 1, so one row of
/// the loop is implied by the others in every configuration. Both forms must
/// move it under gravity alike and conserve its energy, and the joint
/// coordinates' CVODE run must not take the redundant row for a change
/// point. Measured over 10 s: the forms agree to 4e-7 m, energy balances
/// within 3.1e-7 J (joint coordinates, cvode) and 4.8e-7 J (multipliers) of
/// 63 J in play.
TEST(Bricard, BothFormsMoveItAlikeAndConserveItsEnergy) {
  SimRun c = run(BRICARD_SIM, "", "bricard");
  SimRun l = run(BRICARD_LAGRANGE_SIM, "", "bricard_lagrange");
  ASSERT_EQ(c.status, 0) << c.log;
  ASSERT_EQ(l.status, 0) << l.log;
  ASSERT_EQ(c.csv.rows.size(), 1001u) << c.log;
  ASSERT_EQ(l.csv.rows.size(), 1001u) << l.log;
  double apart = 0.0, low = HUGE_VAL, high = -HUGE_VAL;
  for (std::size_t i = 0; i < c.csv.rows.size(); ++i) {
    for (const char* p : {"p3x", "p3y", "p3z"})
      apart = std::max(apart, std::abs(c.csv.rows[i][c.csv.col(p)] - l.csv.rows[i][l.csv.col(p)]));
    low = std::min(low, c.csv.rows[i][c.csv.col("p3y")]), high = std::max(high, c.csv.rows[i][c.csv.col("p3y")]);
  }
  EXPECT_LT(apart, 1e-6);
  EXPECT_GT(high - low, 1.0);  // it moves: the third rod's end falls by more than a rod's length
  EXPECT_LT(energy_residual(c), 1e-6) << c.log;
  EXPECT_LT(energy_residual(l), 1e-6) << l.log;
  EXPECT_FALSE(contains(c.log, "mbgrt: warning")) << c.log;
  EXPECT_TRUE(contains(l.log, "redundant constraints: 1 of 30 lagrange rows implied by the others")) << l.log;
}
