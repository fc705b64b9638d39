// Joint constraints: assembly of the initial state, consistent initial values
// for the index-2 (GGL) DAE under IDA, drift and violation reports, and the
// --constraint-report file. The pendulum has closed forms for all of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <tuple>

#include "constrained_models.hpp"
#include "constraints.hpp"
#include "harness.hpp"

namespace mbgrt::test {
namespace {

constexpr double kG0 = 9.81;

struct ConstrainedRun {
  RunResult r;
  Csv report;  ///< the --constraint-report file
};

ConstrainedRun run_with_report(Model& m, std::vector<std::string> args) {
  const std::string path = temp_path("constraints") + ".csv";
  args.push_back("--constraint-report");
  args.push_back(path);
  ConstrainedRun out{run(m, args), {}};
  out.report = parse_csv(read_file(path));
  std::filesystem::remove(path);
  return out;
}

/// Full precision, so a --set value is the double the test computed.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// The number right after `label` in `text`, or NaN.
double number_after(const std::string& text, const std::string& label) {
  const auto pos = text.find(label);
  if (pos == std::string::npos) return std::nan("");
  return std::strtod(text.c_str() + pos + label.size(), nullptr);
}

double column_max(const Csv& csv, const std::string& name) {
  double m = 0.0;
  for (std::size_t i = 0; i < csv.rows.size(); ++i) m = std::max(m, std::abs(csv.at(i, name)));
  return m;
}

// ---- assembly -------------------------------------------------------------------

/// Start 5 % too far out at 0.6 rad from the downward vertical, moving along
/// the circle at 0.8 m/s and outwards at 0.3 m/s. The minimum-norm steps are
/// radial: assembly must pull the mass in along the rod (same angle) and
/// remove the radial velocity only.
constexpr double kTheta = 0.6, kTangential = 0.8, kRadial = 0.3, kStretch = 1.05;

std::vector<std::string> perturbed_start(bool only_the_start = true) {
  const double s = std::sin(kTheta), c = std::cos(kTheta);
  std::vector<std::string> args{"--set", "x0=" + num(kStretch * s),
                                "--set", "y0=" + num(-kStretch * c),
                                "--set", "u0=" + num(kTangential * c + kRadial * s),
                                "--set", "v0=" + num(kTangential * s - kRadial * c)};
  if (only_the_start) args.insert(args.end(), {"--t-end", "0"});
  return args;
}

/// Checks the assembled first row of a run from perturbed_start().
void expect_assembled(const ConstrainedRun& run) {
  ASSERT_EQ(run.r.status, 0) << run.r.err;
  const Csv csv = parse_csv(run.r.csv);
  ASSERT_EQ(csv.rows.size(), 1u);
  const double x = csv.at(0, "x"), y = csv.at(0, "y"), u = csv.at(0, "u"), v = csv.at(0, "v");
  EXPECT_NEAR(std::hypot(x, y), 1.0, 1e-12) << "on the circle";
  EXPECT_NEAR(std::atan2(x, -y), kTheta, 1e-12) << "angle kept";
  EXPECT_NEAR(x * u + y * v, 0.0, 1e-12) << "no radial velocity";
  EXPECT_NEAR(u * std::cos(kTheta) + v * std::sin(kTheta), kTangential, 1e-12)
      << "tangential velocity kept";

  ASSERT_EQ(run.report.rows.size(), 1u);
  EXPECT_LE(run.report.at(0, "max_abs_g"), 1e-12);
  EXPECT_LE(run.report.at(0, "max_abs_gdot"), 1e-12);

  // The summary: residuals and how far assembly moved the state. The largest
  // position change is 0.05 m along the rod, projected on x or y.
  const std::string& err = run.r.err;
  EXPECT_LE(number_after(err, "assembly: |g| "), 1e-12) << err;
  EXPECT_LE(number_after(err, ", |gdot| "), 1e-12) << err;
  const double proj = std::max(std::sin(kTheta), std::cos(kTheta));
  EXPECT_NEAR(number_after(err, "moved positions by "), (kStretch - 1.0) * proj,
              0.01 * (kStretch - 1.0) * proj)
      << err;  // printed with two digits
  EXPECT_NEAR(number_after(err, "velocities by "), kRadial * proj, 0.01 * kRadial * proj) << err;
  const std::string line = err.substr(std::min(err.find("assembly: "), err.size()));
  EXPECT_GE(number_after(line, " after "), 2) << "a nonlinear g needs more than one step\n" << err;
  EXPECT_LE(number_after(line, " after "), 10) << "Gauss-Newton converges quadratically\n" << err;
}

TEST(Assembly, LagrangePendulumFromAPerturbedStart) {
  GglPendulum m;
  ConstrainedRun run = run_with_report(m, perturbed_start());
  expect_assembled(run);
  if (HasFailure()) return;

  // Consistent initial values computed by the runtime: the rod tension per
  // unit length lambda = m (u^2 + v^2 - g0 y) / L^2 with |(u, v)| = 0.8 and
  // y = -cos(theta); mu = 0; u' = -x lambda / m; x' = u.
  const Csv csv = parse_csv(run.r.csv);
  const double lambda = kTangential * kTangential + kG0 * std::cos(kTheta);
  EXPECT_NEAR(csv.at(0, "lambda"), lambda, 1e-7);
  EXPECT_NEAR(csv.at(0, "mu"), 0.0, 1e-9);
  EXPECT_NEAR(csv.at(0, "udot"), -csv.at(0, "x") * lambda, 1e-7);
  EXPECT_NEAR(csv.at(0, "vdot"), -csv.at(0, "y") * lambda - kG0, 1e-7);
  EXPECT_NEAR(csv.at(0, "xdot"), csv.at(0, "u"), 1e-9);
  EXPECT_TRUE(Contains(run.r.err, "initial values: y' of 4 states and 2 algebraic unknowns"));
  EXPECT_TRUE(Contains(run.r.err, "(2 constraint rows differentiated once)"));
  EXPECT_LE(number_after(run.r.err, "differentiated once), residual "), 1e-12) << run.r.err;
}

TEST(Assembly, PenaltyPendulumFromAPerturbedStart) {
  PenaltyPendulum m;
  ConstrainedRun run = run_with_report(m, perturbed_start());
  expect_assembled(run);
  EXPECT_EQ(run.r.err.find("initial values:"), std::string::npos) << "an ODE has no y' to solve";
}

TEST(Assembly, AStartOnTheCircleIsLeftAlone) {
  GglPendulum m;  // horizontal, at rest: already consistent
  RunResult r = run(m, {"--t-end", "0"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "after 0 iterations"));
  EXPECT_TRUE(Contains(r.err, "moved positions by 0, velocities by 0"));
  const Csv csv = parse_csv(r.csv);
  EXPECT_EQ(csv.at(0, "x"), 1.0);
  EXPECT_EQ(csv.at(0, "y"), 0.0);
  // Released horizontally from rest: no tension yet, free fall.
  EXPECT_NEAR(csv.at(0, "lambda"), 0.0, 1e-9);
  EXPECT_NEAR(csv.at(0, "vdot"), -kG0, 1e-9);
}

TEST(Assembly, TwoCompatibleConstraintsPinTheMass) {
  // A wall at x = 0.5 and the rod leave one point, (0.5, -sqrt(0.75)) near
  // the start, and no velocity: the mass must stay there under gravity.
  GglPendulum m(true);
  std::vector<std::string> args = perturbed_start(false);
  args.insert(args.end(), {"--set", "wall=0.5", "--t-end", "0.5", "--interval", "0.25"});
  ConstrainedRun run = run_with_report(m, args);
  ASSERT_EQ(run.r.status, 0) << run.r.err;
  const Csv csv = parse_csv(run.r.csv);
  ASSERT_EQ(csv.rows.size(), 3u);
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    EXPECT_NEAR(csv.at(i, "x"), 0.5, 1e-9);
    EXPECT_NEAR(csv.at(i, "y"), -std::sqrt(0.75), 1e-9);
    EXPECT_NEAR(csv.at(i, "u"), 0.0, 1e-9);
    EXPECT_NEAR(csv.at(i, "v"), 0.0, 1e-9);
  }
  EXPECT_LE(column_max(run.report, "max_abs_g"), 1e-9);
}

void expect_assembly_failure(const RunResult& r) {
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "mbgrt: error: assembly failed: constraint `"));
  const bool named = Contains(r.err, "`rod.g[0]` residual") || Contains(r.err, "`wall.g[0]` residual");
  EXPECT_TRUE(named) << r.err;
  EXPECT_TRUE(Contains(r.err, "the joints cannot all be closed from the given joint coordinates; "
                              "check lengths and initial angles"));
  // The least-squares compromise leaves residuals of order 0.1-1, not rounding.
  EXPECT_GT(number_after(r.err, "residual "), 0.05) << r.err;
  EXPECT_LE(number_after(r.err, " after "), 50) << r.err;
  EXPECT_EQ(r.csv, "") << "nothing is integrated, not even a header is written";
  EXPECT_EQ(r.err.find("run summary"), std::string::npos);
}

TEST(Assembly, ContradictoryConstraintsStopWithAClearError) {
  {
    GglPendulum m(true);  // rod of length 1 and a wall at x = 2
    RunResult r = run(m, {});
    expect_assembly_failure(r);
    EXPECT_EQ(m.terminal_calls, 1);
  }
  {
    PenaltyPendulum m(1e6, true);
    RunResult r = run(m, {"--quiet"});
    expect_assembly_failure(r);
  }
}

// ---- lagrange: IDA on the index-2 DAE ------------------------------------------------

TEST(Lagrange, PendulumPeriodMatchesTheAgmClosedForm) {
  // Released horizontally from rest (theta0 = pi/2): after one period the mass
  // is back at (1, 0), after half of it at (-1, 0), and at a quarter it passes
  // the bottom with the tension per unit length 3 m g0. The small-angle period
  // (2 pi sqrt(L/g) = 2.006 s against 2.368 s) would miss by far.
  const double period = pendulum_period(1.0, kG0, std::numbers::pi / 2);
  ASSERT_NEAR(period, 2.0061 * 1.18034, 1e-4);  // K(1/sqrt 2) factor of the 90-degree swing
  GglPendulum m;
  ConstrainedRun run = run_with_report(
      m, {"--t-end", num(period), "--interval", num(period / 40), "--rtol", "1e-10", "--atol",
          "1e-12"});
  ASSERT_EQ(run.r.status, 0) << run.r.err;
  const Csv csv = parse_csv(run.r.csv);
  ASSERT_EQ(csv.rows.size(), 41u);
  EXPECT_NEAR(csv.at(40, "t"), period, 1e-12);
  EXPECT_NEAR(csv.at(40, "y"), 0.0, 1e-6);
  EXPECT_NEAR(csv.at(40, "x"), 1.0, 1e-6);
  EXPECT_NEAR(csv.at(20, "y"), 0.0, 1e-6);
  EXPECT_NEAR(csv.at(20, "x"), -1.0, 1e-6);
  EXPECT_NEAR(csv.at(10, "x"), 0.0, 1e-6);
  EXPECT_NEAR(csv.at(10, "y"), -1.0, 1e-6);
  EXPECT_NEAR(csv.at(10, "lambda"), 3 * kG0, 1e-5);

  // Drift: g and gdot stay at the level of the Newton tolerance.
  ASSERT_EQ(run.report.rows.size(), csv.rows.size());
  EXPECT_EQ(run.report.header, (std::vector<std::string>{"t", "max_abs_g", "max_abs_gdot"}));
  for (std::size_t i = 0; i < csv.rows.size(); ++i) EXPECT_EQ(run.report.at(i, "t"), csv.at(i, "t"));
  EXPECT_LT(column_max(run.report, "max_abs_g"), 1e-9);
  EXPECT_LT(column_max(run.report, "max_abs_gdot"), 1e-9);
  EXPECT_TRUE(Contains(run.r.err, "  constraint drift: position "));
  EXPECT_LT(number_after(run.r.err, "constraint drift: position "), 1e-9);
  EXPECT_LT(number_after(run.r.err, "), velocity "), 1e-9);
  EXPECT_TRUE(Contains(run.r.err, "(rod.g[0] at t = "));
  EXPECT_TRUE(Contains(run.r.err, "(rod.gdot[0] at t = "));
  EXPECT_EQ(run.r.err.find("violation"), std::string::npos);
}

TEST(Lagrange, ShortIntervalsAndTightAtolStillConverge) {
  // Rounding noise delta in the g rows reaches mu as delta / h; with the
  // multipliers' Newton weights scaled by h / interval it weighs
  // delta / (interval atol) whatever the step. At interval * atol of 1e-18
  // s (1e-5 s and 1e-13, 1e-6 s and 1e-12) IDA's steps collapsed (to 1e-21 s)
  // and it stopped with IDA_TOO_MUCH_WORK. The runtime then restarts with
  // the weights scaled by h / 1 s, and the run completes.
  GglPendulum m;
  for (auto [interval, atol, rows] : {std::tuple{"1e-5", "1e-13", 30001u},
                                      std::tuple{"1e-6", "1e-12", 501u}}) {
    const std::string t_end = num(std::strtod(interval, nullptr) * (rows - 1));
    ConstrainedRun run = run_with_report(
        m, {"--t-end", t_end, "--interval", interval, "--rtol", "1e-10", "--atol", atol});
    ASSERT_EQ(run.r.status, 0) << "interval " << interval << "\n" << run.r.err;
    EXPECT_TRUE(Contains(run.r.err, "restarted with those weights scaled by h / 1 s")) << run.r.err;
    const Csv csv = parse_csv(run.r.csv);
    ASSERT_EQ(csv.rows.size(), rows) << interval;
    // Released from rest at y = 0: energy per unit mass u^2/2 + v^2/2 + g0 y stays 0.
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
      const double u = csv.at(i, "u"), v = csv.at(i, "v");
      EXPECT_NEAR(0.5 * (u * u + v * v) + kG0 * csv.at(i, "y"), 0.0, 1e-10) << interval;
    }
    EXPECT_LT(column_max(run.report, "max_abs_g"), 1e-11) << interval;
    EXPECT_LT(column_max(run.report, "max_abs_gdot"), 1e-9) << interval;
  }
}

TEST(Lagrange, ARedundantRowIsFoundAndItsMultipliersHeldAtZero) {
  // The rod stated twice: the same motion as with one row, one of the two
  // rows reported redundant, its multipliers 0 and the tension carried by the
  // other. The two runs take different steps (different Newton matrices), so
  // they agree to the integration error: measured 2.9e-9 at rtol 1e-10.
  const std::vector<std::string> args{"--t-end", "1", "--rtol", "1e-10", "--atol", "1e-12"};
  GglPendulum single;
  RunResult one = run(single, args);
  ASSERT_EQ(one.status, 0) << one.err;
  TwinRodPendulum twin;
  ConstrainedRun two = run_with_report(twin, args);
  ASSERT_EQ(two.r.status, 0) << two.r.err;
  EXPECT_TRUE(Contains(two.r.err, "  redundant constraints: 1 of 2 lagrange rows implied by the others "
                                  "at the assembled state (twin.g[0])"))
      << two.r.err;
  EXPECT_EQ(one.err.find("redundant"), std::string::npos) << one.err;
  const Csv a = parse_csv(one.csv), b = parse_csv(two.r.csv);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    for (const char* col : {"x", "y", "u", "v"}) EXPECT_NEAR(b.at(i, col), a.at(i, col), 1e-8) << col << " row " << i;
    EXPECT_NEAR(b.at(i, "lambda"), a.at(i, "lambda"), 1e-6 * (1 + std::abs(a.at(i, "lambda"))));
  }
  EXPECT_LT(column_max(two.report, "max_abs_g"), 1e-9);
}

TEST(Lagrange, AModelHidingWhereItsMultipliersSitIsRejectedBeforeItRuns) {
  // The same model not saying where its multipliers are: the runtime cannot
  // tell the constraint rows from the others, nor drop the redundant one. It
  // does not guess from sizes: it stops before the run, naming what is wrong.
  TwinRodPendulum twin(/*hide_multipliers=*/true);
  RunResult r = run(twin, {"--t-end", "1"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(Contains(r.err, "breaks the runtime contract: unknown_role() calls 'rod.lambda' (entry 4) a "
                              "multiplier, but no constraint row puts its multiplier there"))
      << r.err;
  EXPECT_TRUE(parse_csv(r.csv).rows.empty());
}

struct ReleaseCase {
  double L, theta0;
};

void PrintTo(const ReleaseCase& c, std::ostream* os) { *os << "L " << c.L << " theta0 " << c.theta0; }

class ReleasedFromRest : public ::testing::TestWithParam<ReleaseCase> {};

TEST_P(ReleasedFromRest, ReturnsAfterOnePeriodAtModerateTolerances) {
  // Unlike the horizontal start of a unit rod, g = (x^2 + y^2 - L^2)/2 is
  // not exactly zero in floating point here, and that rounding noise reaches
  // mu amplified by 1/h. With IDA's own first step for a start from rest
  // (~1e-11 s) and plain atol weights on the multipliers, the Newton
  // iteration failed at or near t = 0 in both cases.
  const auto [L, theta0] = GetParam();
  const double period = pendulum_period(L, kG0, theta0);
  const double x0 = L * std::sin(theta0), y0 = -L * std::cos(theta0);
  GglPendulum m;
  ConstrainedRun run = run_with_report(
      m, {"--set", "L=" + num(L), "--set", "x0=" + num(x0), "--set", "y0=" + num(y0), "--t-end",
          num(period), "--interval", num(period / 20), "--rtol", "1e-8", "--atol", "1e-10"});
  ASSERT_EQ(run.r.status, 0) << run.r.err;
  const Csv csv = parse_csv(run.r.csv);
  ASSERT_EQ(csv.rows.size(), 21u);
  // rtol 1e-8 over one period: measured up to 4e-8 L.
  EXPECT_NEAR(csv.at(20, "x"), x0, 1e-6 * L);
  EXPECT_NEAR(csv.at(20, "y"), y0, 1e-6 * L);
  EXPECT_NEAR(csv.at(10, "x"), -x0, 1e-6 * L);
  EXPECT_NEAR(csv.at(10, "y"), y0, 1e-6 * L);
  EXPECT_LT(column_max(run.report, "max_abs_g"), 1e-8 * L * L);  // measured 4e-10 L^2
  // A healthy run, not one that limps through on repeated step cuts.
  EXPECT_LT(summary_number(run.r.err, "steps"), 2000) << run.r.err;
}

INSTANTIATE_TEST_SUITE_P(Lagrange, ReleasedFromRest,
                         ::testing::Values(ReleaseCase{1.0, 0.3}, ReleaseCase{20.0, 2.0}),
                         [](const auto& info) { return info.index == 0 ? "short_rod" : "long_rod"; });

TEST(Lagrange, ANonFiniteConstraintRowIsNamedAsTheConstraint) {
  GglPendulum m;
  RunResult r = run(m, {"--set", "poison_after=0.3"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "the residual of constraint 'rod.gdot[0]' became NaN"));
  EXPECT_TRUE(Contains(r.err, "check the equations that involve constraint 'rod.gdot[0]'"));
  EXPECT_TRUE(Contains(r.err, "solver ida stopped: IDA_"));
  const double t = reported_time(r.err);
  EXPECT_GT(t, 0.3);
  EXPECT_LT(t, 0.35);
  // IDA may step past an output time and interpolate back, so the row at
  // t = 0.3 may or may not be written before the step that fails.
  const std::size_t rows = parse_csv(r.csv).rows.size();
  EXPECT_GE(rows, 6u);
  EXPECT_LE(rows, 7u);
}

/// A generator bug: state_count() disagrees with differential_ids().
class MiscountedPendulum : public GglPendulum {
 public:
  std::size_t state_count() const override { return 5; }
};

TEST(Lagrange, AModelBreakingTheStateLayoutIsRejected) {
  MiscountedPendulum m;
  RunResult r = run(m, {});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "breaks the runtime contract"));
  EXPECT_TRUE(Contains(r.err, "'rod.lambda'"));
  EXPECT_EQ(r.csv, "");
}

/// Generator bugs in the layout the runtime is told (it discovers none of it).
class JacobianlessPendulum : public GglPendulum {
 public:
  void constraint_jacobian_pattern(std::vector<long>& starts, std::vector<long>& columns) const override {
    starts.clear();
    columns.clear();
  }
};
class VelocityReadingPendulum : public GglPendulum {
 public:
  void constraint_jacobian_pattern(std::vector<long>& starts, std::vector<long>& columns) const override {
    starts = {0, 3};
    columns = {0, 1, 2};
  }
};
class UnsaidPenaltyPendulum : public PenaltyPendulum {
 public:
  UnknownRole unknown_role(std::size_t) const override { return UnknownRole::unspecified; }
};

TEST(Lagrange, ALayoutTheModelDoesNotStateIsRejectedBeforeItRuns) {
  JacobianlessPendulum no_jacobian;
  VelocityReadingPendulum reads_velocity;
  UnsaidPenaltyPendulum unsaid;
  const std::pair<Model*, std::string> cases[] = {
      {&no_jacobian, "constraint_jacobian_pattern() gives 0 row starts for 1 position constraints"},
      {&reads_velocity, "constraint 'rod.g[0]' reads 'mass.u', which unknown_role() calls a velocity: a position "
                        "constraint reads positions only"},
      {&unsaid, "unknown_role() says 'mass.x' (entry 0) is unspecified, but it is a state"},
  };
  for (const auto& [model, message] : cases) {
    RunResult r = run(*model, {});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(Contains(r.err, "breaks the runtime contract: " + message)) << r.err;
    EXPECT_EQ(r.csv, "");
  }
}

/// G with the wrong sign: Gauss-Newton then walks away from g = 0.
class FlippedJacobianPendulum : public GglPendulum {
 public:
  void constraint_jacobian(double t, const double* x, double* values) override {
    GglPendulum::constraint_jacobian(t, x, values);
    values[0] = -values[0];
    values[1] = -values[1];
  }
};

TEST(Assembly, MovesThePositionsAlongTheModelsOwnJacobian) {
  // The runtime takes G from the model, not from differences: a wrong G
  // cannot close the rod from a start off the circle...
  FlippedJacobianPendulum flipped;
  RunResult bad = run(flipped, {"--set", "x0=1.2"});
  EXPECT_EQ(bad.status, 1) << bad.err;
  EXPECT_TRUE(Contains(bad.err, "assembly failed: constraint `rod.g[0]` residual")) << bad.err;
  // ... while the right one does.
  GglPendulum right;
  RunResult good = run(right, {"--set", "x0=1.2", "--t-end", "0.1"});
  EXPECT_EQ(good.status, 0) << good.err;
}

// ---- penalty: violation against stiffness ---------------------------------------------

/// Largest |g| over a 1 s run from horizontal (the mass passes the bottom at
/// about 0.59 s, where the rod carries 3 m g0).
double penalty_violation(double k) {
  PenaltyPendulum m(k);
  ConstrainedRun run = run_with_report(m, {});
  EXPECT_EQ(run.r.status, 0) << run.r.err;
  EXPECT_TRUE(Contains(run.r.err, "  largest constraint violation: position "));
  EXPECT_EQ(run.r.err.find("drift"), std::string::npos);
  const double from_report = column_max(run.report, "max_abs_g");
  // The summary prints the same peak with two digits.
  EXPECT_NEAR(number_after(run.r.err, "largest constraint violation: position "), from_report,
              0.05 * from_report);
  return from_report;
}

TEST(Penalty, ViolationShrinksAsTheStiffnessGrows) {
  // Quasi-static stretch: k g |G| = tension, so g ~ 3 m g0 / k ~ 29 / k.
  const double v4 = penalty_violation(1e4), v6 = penalty_violation(1e6),
               v8 = penalty_violation(1e8);
  for (auto [k, v] : {std::pair{1e4, v4}, std::pair{1e6, v6}, std::pair{1e8, v8}}) {
    EXPECT_GT(k * v, 10.0) << "k = " << k;
    EXPECT_LT(k * v, 60.0) << "k = " << k;
  }
  EXPECT_LT(v6, v4 / 30) << v4 << " " << v6;
  EXPECT_LT(v8, v6 / 30) << v6 << " " << v8;
}

// ---- the report file and the unconstrained path ------------------------------------------

TEST(ConstraintReport, UnconstrainedModelsWriteZerosAndNoSummaryLines) {
  Decay m;
  ConstrainedRun run = run_with_report(m, {});
  ASSERT_EQ(run.r.status, 0) << run.r.err;
  ASSERT_EQ(run.report.rows.size(), 21u);
  EXPECT_EQ(column_max(run.report, "max_abs_g"), 0.0);
  EXPECT_EQ(column_max(run.report, "max_abs_gdot"), 0.0);
  for (const char* text : {"assembly", "initial values", "constraint"})
    EXPECT_EQ(run.r.err.find(text), std::string::npos) << text << "\n" << run.r.err;
}

TEST(ConstraintReport, UnwritablePathExits2) {
  GglPendulum m;
  RunResult r = run(m, {"--constraint-report", "/nonexistent-dir/c.csv"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "/nonexistent-dir/c.csv"));
}

TEST(ConstraintReport, IsListedInHelp) {
  GglPendulum m;
  RunResult r = run(m, {"--help"}, false);
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(Contains(r.out, "--constraint-report"));
}

TEST(Lagrange, OtherSolversAreRejectedForTheDae) {
  GglPendulum m;
  RunResult r = run(m, {"--solver", "cvode"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "--solver ida"));
}

TEST(Lagrange, InitialValuesDoNotCallAFullRankSystemRedundantBecauseOfItsUnits) {
  // A pendulum bob of 1e12 kg: its multiplier's column carries 1 / m beside
  // the accelerations' 1 and, without column scaling, the rank test took it
  // for a dependent one ("the multipliers are not unique"). The motion does
  // not depend on the mass: the bob still passes the bottom at a quarter period.
  const double period = pendulum_period(1.0, kG0, std::numbers::pi / 2);
  GglPendulum m;
  ConstrainedRun run = run_with_report(m, {"--set", "m=1e12", "--t-end", num(period / 4), "--interval",
                                           num(period / 40), "--rtol", "1e-10", "--atol", "1e-12"});
  ASSERT_EQ(run.r.status, 0) << run.r.err;
  EXPECT_TRUE(Contains(run.r.err, "initial values: ")) << run.r.err;
  EXPECT_FALSE(Contains(run.r.err, "not unique")) << run.r.err;
  const Csv csv = parse_csv(run.r.csv);
  EXPECT_NEAR(csv.at(10, "x"), 0.0, 1e-6);
  EXPECT_NEAR(csv.at(10, "y"), -1.0, 1e-6);
}


/// The twin-rod pendulum telling the runtime that every residual row may
/// read every unknown: a pattern, if a dense one, for the sparse rates.
class PatternedTwinRod : public TwinRodPendulum {
 public:
  bool residual_sparsity(std::vector<long>& column_starts, std::vector<long>& rows) const override {
    const long n = static_cast<long>(size());
    column_starts.clear();
    rows.clear();
    for (long j = 0; j <= n; ++j) column_starts.push_back(j * n);
    for (long j = 0; j < n; ++j)
      for (long i = 0; i < n; ++i) rows.push_back(i);
    return true;
  }
};

TEST(Lagrange, TheSparseRatesAreTheDenseOnes) {
  // The rates a large model's Newton matrix gives on its sparsity pattern
  // (sparse QR) are those of the dense minimum-norm solve, with a redundant
  // row's multipliers held at 0, in both forms: the DAE's (position rows
  // differentiated) and the index-1 form of a step across a change point.
  PatternedTwinRod model;
  std::vector<double> y(model.size()), yp(model.size());
  model.initial(0.0, y.data(), yp.data());
  detail::ConstraintShape shape = detail::constraint_shape(model);
  y[0] = 1.0, y[1] = 0.0, y[2] = 0.0, y[3] = 0.3;  // on the unit circle, moving along it
  shape.redundant = detail::find_redundant_constraints(model, shape, 0.0, y.data()).redundant;
  ASSERT_EQ(shape.redundant.size(), 1u);
  for (bool index_one : {false, true}) {
    detail::RatesOptions dense, sparse;
    dense.index_one = sparse.index_one = index_one;
    sparse.sparse_from = 0;
    std::vector<double> y1 = y, yp1 = yp, y2 = y, yp2 = yp;
    const detail::InitialValuesReport a = detail::consistent_initial_values(model, shape, 0.0, y1.data(), yp1.data(), dense);
    const detail::InitialValuesReport b = detail::consistent_initial_values(model, shape, 0.0, y2.data(), yp2.data(), sparse);
    ASSERT_TRUE(a.ok) << a.error;
    ASSERT_TRUE(b.ok) << b.error;
    EXPECT_EQ(a.rank, b.rank);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(yp2[i], yp1[i], 1e-12 * (1 + std::abs(yp1[i]))) << i;
    for (std::size_t i = 4; i < model.size(); ++i) EXPECT_NEAR(y2[i], y1[i], 1e-9 * (1 + std::abs(y1[i]))) << i;
    // at (1, 0) the rod pulls along x only: u' = -v^2 / L, v' = -g0
    EXPECT_NEAR(yp1[2], -0.09, 1e-12);
    EXPECT_NEAR(yp1[3], -kG0, 1e-12);
  }
}

}  // namespace
}  // namespace mbgrt::test
