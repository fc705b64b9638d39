// extremes_test.cpp — issue 5's stability suite: models pushed to the edges
// where simulators usually print NaNs or hang. Each test states what must
// happen: a result within a stated tolerance of an independent reference, or
// a clean stop (exit 1) whose report names the state, the time and the likely
// cause. No run may write a non-finite number to its CSV.
//
// The buckling coupler (a flexible crank-rocker whose coupler buckles and
// stops with a report) lives in flexible_test.cpp:
// CrankRockerFlexible.HeavyRockerBucklesTheCouplerAtItsEulerLoadAndTheRunStopsWithAReport.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cmath>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

constexpr double kG = 9.81;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// Every number in the CSV is finite (the runtime stops before writing NaN).
void expect_all_finite(const SimRun& r, const std::string& what) {
  for (const auto& row : r.csv.rows)
    for (double v : row) ASSERT_TRUE(std::isfinite(v)) << what << ": non-finite value in the CSV at t = " << row[0];
}

// ---- an independent reference: two uniform rods of masses m1, m2 ----
// Absolute angles th1, th2 from the downward vertical, rod length l:
//   T = 1/2 (m1 l^2/3 + m2 l^2) w1^2 + 1/2 (m2 l^2/3) w2^2 + m2 l^2/2 cos(th1 - th2) w1 w2
//   V = -(m1/2 + m2) g l cos th1 - m2 g l/2 cos th2
// written in the joint angles q1 = th1, q2 = th2 - th1.
struct TwoRods {
  double m1, m2, l = 0.5;
  std::array<double, 4> operator()(const std::array<double, 4>& y) const {
    const double q1 = y[0], q2 = y[1], u1 = y[2], u2 = y[3];
    const double c = std::cos(q2), s = -std::sin(q2);  // of th1 - th2 = -q2
    const double M11 = m1 * l * l / 3 + m2 * l * l, M12 = m2 * l * l / 2 * c, M22 = m2 * l * l / 3;
    const double f1 = -m2 * l * l / 2 * s * (u1 + u2) * (u1 + u2) - (m1 / 2 + m2) * kG * l * std::sin(q1);
    const double f2 = m2 * l * l / 2 * s * u1 * u1 - m2 * kG * l / 2 * std::sin(q1 + q2);
    const double A = M11 + 2 * M12 + M22, B = M12 + M22, C = M22;  // J^T M J with th = J q
    const double r1 = f1 + f2, r2 = f2;
    const double det = A * C - B * B;
    return {u1, u2, (C * r1 - B * r2) / det, (A * r2 - B * r1) / det};
  }
  /// q1, q2 at time T from rest at (0.3, 0.3): RK4 with a 1e-5 s step.
  std::array<double, 2> at(double T) const {
    std::array<double, 4> y{0.3, 0.3, 0, 0};
    const long steps = std::lround(T / 1e-5);
    for (long n = 0; n < steps; ++n) y = rk4_step(y, 1e-5, *this);
    return {y[0], y[1]};
  }
};

}  // namespace

// ---- penalty joints from 1e3 to 1e12 N/m (chain_2_penalty) ----
namespace {

/// The chain's two penalty joints at stiffness k (N/m); their damping follows (2 sqrt(m k)).
std::string penalty(double k) {
  char s[32];
  std::snprintf(s, sizeof s, "%g", k);
  return std::string("--set j1.stiffness=") + s + " --set j2.stiffness=" + s;
}

double q_error(const SimRun& r, const std::array<double, 2>& ref) {
  return std::max(std::abs(r.csv.at(1.0, "q1") - ref[0]), std::abs(r.csv.at(1.0, "q2") - ref[1]));
}

}  // namespace

TEST(Extremes, PenaltyJointsFrom1e4To1e9UnderCvodeConvergeToTheRigidJointsAsOneOverK) {
  // The penalty joint is a spring: the chain differs from the rigid double
  // pendulum by its compliance, ~1/k. Measured q error at t = 1 s (rtol 1e-10):
  // 7.6e-3 (1e4), 8.2e-5 (1e6), 1.7e-7 (1e9) rad: 92 and 480 times closer for
  // 100 and 1000 times stiffer. (At 1e3 the joints stretch 2.2 cm, more than
  // a joint may give: that run stops, PenaltyJointsStretchedBeyondACentimetreStop.)
  const std::array<double, 2> ref = TwoRods{1, 1}.at(1.0);
  double previous = HUGE_VAL;
  for (double k : {1e4, 1e6, 1e9}) {
    SimRun r = run(CHAIN2_PENALTY_SIM, penalty(k) + " --solver cvode --rtol 1e-10 --atol 1e-12", "penalty_cvode");
    ASSERT_EQ(r.status, 0) << "k = " << k << "\n" << r.log;
    expect_all_finite(r, "cvode");
    const double err = q_error(r, ref);
    EXPECT_LT(err, previous / 50) << "k = " << k;
    previous = err;
  }
  EXPECT_LT(previous, 1e-6);
}

TEST(Extremes, PenaltyJointsStretchedBeyondACentimetreStop) {
  // 1e3 N/m holds a 1 kg rod 2.2 cm off its joint: not a joint any more.
  SimRun r = run(CHAIN2_PENALTY_SIM, penalty(1e3) + " --solver cvode --rtol 1e-10 --atol 1e-12", "penalty_1e3_cvode");
  EXPECT_EQ(r.status, 1) << r.log;
  expect_all_finite(r, "cvode");
  EXPECT_TRUE(contains(r.log, "penalty joint row j1.cn[2] g is stretched by 0.01")) << r.log;
  EXPECT_TRUE(contains(r.log, "a penalty joint too soft for its loads")) << r.log;
  EXPECT_GT(r.csv.rows.back()[0], 0.05);  // the rows up to there are written
}

TEST(Extremes, PenaltyJointsOf1e12StopCvodeWithTheStiffnessNamed) {
  // At 1e12 N/m the joints' fastest mode is ~1e7 1/s; CVODE at rtol 1e-10
  // runs out of steps in the first millisecond. The stop must say so in model
  // terms, not print NaN rows.
  SimRun r = run(CHAIN2_PENALTY_SIM, penalty(1e12) + " --solver cvode --rtol 1e-10 --atol 1e-12", "penalty_1e12_cvode");
  EXPECT_EQ(r.status, 1) << r.log;
  expect_all_finite(r, "cvode");
  EXPECT_TRUE(contains(r.log, "CV_TOO_MUCH_WORK")) << r.log;
  EXPECT_TRUE(contains(r.log, "the penalty joints' stiffness sets such a rate")) << r.log;
}

TEST(Extremes, PenaltyJointsUnderExplicitSolversAreReportedUnstableOrStabilityLimited) {
  const std::array<double, 2> ref = TwoRods{1, 1}.at(1.0);
  // rk4 at its default step (1 ms) is beyond the stability limit from 1e6 on:
  // the run stops at the first non-finite value and says why.
  SimRun rk4 = run(CHAIN2_PENALTY_SIM, penalty(1e6) + " --solver rk4", "penalty_rk4");
  EXPECT_EQ(rk4.status, 1) << rk4.log;
  expect_all_finite(rk4, "rk4");
  EXPECT_TRUE(contains(rk4.log, "became NaN")) << rk4.log;
  EXPECT_TRUE(contains(rk4.log, "rk4 is stable only for steps below")) << rk4.log;
  EXPECT_TRUE(contains(rk4.log, "(this run's: 0.001 s)")) << rk4.log;
  // dopri5 follows the stiff joints with tiny steps: right, and said to be stability-limited.
  SimRun slow = run(CHAIN2_PENALTY_SIM, penalty(1e9) + " --solver dopri5 --rtol 1e-10 --atol 1e-12", "penalty_dopri5");
  ASSERT_EQ(slow.status, 0) << slow.log;
  EXPECT_LT(q_error(slow, ref), 1e-6);
  EXPECT_TRUE(contains(slow.log, "steps limited by stability, not accuracy")) << slow.log;
  // A soft joint is not stiff: no such line.
  SimRun soft = run(CHAIN2_PENALTY_SIM, penalty(1e4) + " --solver dopri5 --rtol 1e-10 --atol 1e-12", "penalty_soft");
  ASSERT_EQ(soft.status, 0) << soft.log;
  EXPECT_FALSE(contains(soft.log, "steps limited by stability")) << soft.log;
  // At 1e12 dopri5 cannot take a step: it stops and points to an implicit solver.
  SimRun stuck = run(CHAIN2_PENALTY_SIM, penalty(1e12) + " --solver dopri5", "penalty_1e12_dopri5");
  EXPECT_EQ(stuck.status, 1) << stuck.log;
  expect_all_finite(stuck, "dopri5");
  EXPECT_TRUE(contains(stuck.log, "try --solver cvode")) << stuck.log;
}

// ---- masses and inertias of 1e-9 beside 1e3 (two_rods) ----
TEST(Extremes, MassesOf1e3Beside1e9FollowTheHandWrittenDoublePendulum) {
  // The light rod rides on the heavy one (or the heavy one hangs from a light
  // one); both the multiplier (IDA) and the joint-coordinate (CVODE) forms
  // must give the reference's joint angles to 1e-6 rad at t = 1 s.
  for (const auto& [m1, m2] : {std::pair{1e3, 1e-9}, std::pair{1e-9, 1e3}}) {
    const std::array<double, 2> ref = TwoRods{m1, m2}.at(1.0);
    char masses[80];
    std::snprintf(masses, sizeof masses, "--set m1=%g --set m2=%g", m1, m2);
    SimRun r = run(TWO_RODS_COORDINATES_SIM, masses, "two_rods_masses");
    ASSERT_EQ(r.status, 0) << masses << '\n' << r.log;
    expect_all_finite(r, "coordinates");
    EXPECT_LT(q_error(r, ref), 1e-6) << masses;
  }
}

TEST(Extremes, WithMultipliersALightRodIsResolvedAtTheModelsOwnAtol) {
  // The light rod's momenta are ~1e-9 kg m/s. With one atol for every
  // unknown, the model's 1e-10 left them a 10% error budget and q2 at t = 1 s
  // was 1.5e-5 rad off (measured). Each momentum's absolute tolerance is now
  // atol times its inertia (reduce/nominal.hpp), a bound on the light rod's
  // velocity as on the heavy one's: within 1e-6 rad at the model's own
  // tolerances (measured 4.4e-8), and at tighter ones.
  const std::array<double, 2> ref = TwoRods{1e3, 1e-9}.at(1.0);
  SimRun loose = run(TWO_RODS_SIM, "--set m1=1e3 --set m2=1e-9", "two_rods_light_loose");
  ASSERT_EQ(loose.status, 0) << loose.log;
  expect_all_finite(loose, "lagrange");
  EXPECT_LT(q_error(loose, ref), 1e-6);
  EXPECT_FALSE(contains(loose.log, "peaked within")) << loose.log;
  SimRun tight = run(TWO_RODS_SIM, "--set m1=1e3 --set m2=1e-9 --rtol 1e-10 --atol 1e-13", "two_rods_light_tight");
  ASSERT_EQ(tight.status, 0) << tight.log;
  expect_all_finite(tight, "lagrange");
  EXPECT_LT(q_error(tight, ref), 1e-6);
  // A heavy rod hanging from a 1e-9 kg one: IDA's Newton matrix for the
  // consistent start is numerically rank-deficient (mass ratio 1e12); the run
  // stops at t = 0 and says so, with no rows of NaN.
  SimRun heavy = run(TWO_RODS_SIM, "--set m1=1e-9 --set m2=1e3", "two_rods_heavy_below_light");
  EXPECT_EQ(heavy.status, 1) << heavy.log;
  expect_all_finite(heavy, "lagrange");
  EXPECT_TRUE(contains(heavy.log, "consistent initial values")) << heavy.log;
}

// ---- spin far above the beam's first frequency (rotating_beam) ----
TEST(Extremes, SpinSevenTimesTheFirstFrequencyIsBoundedWithGeometricStiffnessAndReportedWithout) {
  // Omega_s = 20 rad/s against a first bending frequency of 2.91 rad/s at rest.
  // With geometric stiffness the blade stiffens with the spin and stays small;
  // the linear model loses its stiffness once the spin passes 2.91 rad/s and
  // must stop with the mode named, not run on or print NaN.
  SimRun stiff = run(ROTATING_BEAM_SIM, "--set Omega_s=20", "rotating_beam_ws20");
  ASSERT_EQ(stiff.status, 0) << stiff.log;
  expect_all_finite(stiff, "rotating_beam");
  // measured: 1.63 m at t = 5 s (of an 8 m blade, while the hub accelerates),
  // 0.019 m at t = 20 s, 5 s after the spin-up ends
  EXPECT_LT(stiff.csv.max_abs("tip_deflection"), 2.0);
  EXPECT_LT(std::abs(stiff.csv.rows.back()[stiff.csv.col("tip_deflection")]), 0.05);
  SimRun linear = run(ROTATING_BEAM_LINEAR_SIM, "--set Omega_s=20", "rotating_beam_linear_ws20");
  EXPECT_EQ(linear.status, 1) << linear.log;
  expect_all_finite(linear, "rotating_beam_linear");
  EXPECT_TRUE(contains(linear.log, "state 'blade.eta.q[1]'")) << linear.log;
  EXPECT_TRUE(contains(linear.log, "without geometric stiffness")) << linear.log;
}

// ---- a chain of spherical joints, aligned (models/spherical_chain.mbg) ----
TEST(Extremes, AnAlignedSphericalChainFallsAlikeWithMultipliersAndQuaternions) {
  // Three rods in one straight line, every ball joint aligned: no angle set
  // is used (absolute poses with multipliers; relative quaternions in joint
  // coordinates), so nothing is singular. Both forms must agree and keep the
  // energy.
  SimRun lagrange = run(SPHERICAL_CHAIN_SIM, "", "spherical_chain");
  SimRun coordinates = run(SPHERICAL_CHAIN_COORDINATES_SIM, "--solver cvode --rtol 1e-10 --atol 1e-12",
                           "spherical_chain_coordinates");
  ASSERT_EQ(lagrange.status, 0) << lagrange.log;
  ASSERT_EQ(coordinates.status, 0) << coordinates.log;
  expect_all_finite(lagrange, "lagrange");
  expect_all_finite(coordinates, "coordinates");
  EXPECT_NEAR(lagrange.csv.at(0.0, "x"), 1.5, 1e-12);
  EXPECT_GT(lagrange.csv.max_deviation("z"), 0.5);  // it falls and swings
  EXPECT_LT(max_difference(lagrange.csv, coordinates.csv, "x"), 1e-6);
  EXPECT_LT(max_difference(lagrange.csv, coordinates.csv, "z"), 1e-6);
  EXPECT_LT(lagrange.csv.max_deviation("E"), 1e-6);
  EXPECT_LT(coordinates.csv.max_deviation("E"), 1e-6);
}

// ---- a four-bar through its change points (crank_rocker as a parallelogram) ----
TEST(Extremes, AParallelogramFourBarRunsThroughItsChangePointsOnItsBranch) {
  // Crank = rocker and coupler = ground: at crank angles 0 and pi all four
  // links are collinear, the joint rows lose rank and the mechanism may fold
  // into the antiparallelogram. The motor drives it through the first at
  // t = 0.28 s and, accelerating to 74 rad/s, through 2 s: IDA steps across
  // each (solvers/change_point.hpp; measured 35 steps across) and the
  // mechanism stays a parallelogram, crank and rocker turning alike
  // (measured within 2.3e-8 rad/s); on the other branch they would not.
  SimRun r = run(CRANK_ROCKER_SIM, "--set a1=0.2 --set a3=0.2 --set a2=0.559 --set theta1_0=0.5 --t-end 2",
                 "parallelogram");
  expect_all_finite(r, "crank_rocker");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 2001u) << r.log;
  EXPECT_TRUE(contains(r.log, "change points of the joints, where their rows became dependent")) << r.log;
  double worst = 0.0;
  for (const auto& row : r.csv.rows)
    worst = std::max(worst, std::abs(row[r.csv.col("omega_crank")] - row[r.csv.col("omega_rocker")]));
  EXPECT_LT(worst, 1e-6) << r.log;
  EXPECT_GT(std::abs(r.csv.rows.back()[r.csv.col("omega_crank")]), 50.0) << r.log;  // it turned many times
}

// ---- 1000 s of a conservative system (pendulum, multipliers) ----
TEST(Extremes, AThousandSecondsOfThePendulumDriftInEnergyByLessThanAMicrojoule) {
  // Released from the horizontal (E = 0 with the pivot as the zero of the
  // potential): m g L = 9.81 J is the energy that moves. Measured at the
  // model's rtol 1e-10: 3.1e-7 J over 1000 s (about 1600 swings).
  SimRun r = run(MB_PENDULUM_SIM, "--t-end 1000 --interval 0.5", "pendulum_1000s");
  ASSERT_EQ(r.status, 0) << r.log;
  expect_all_finite(r, "pendulum");
  ASSERT_NEAR(r.csv.rows.back()[0], 1000.0, 1e-9);
  const double drift = r.csv.max_deviation("E");
  RecordProperty("energy_drift_J", std::to_string(drift));
  std::printf("pendulum, 1000 s: energy drift %.3g J (m g L = 9.81 J)\n", drift);
  EXPECT_LT(drift, 1e-6);
}
