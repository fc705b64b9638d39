// vehicle_test.cpp — vehicle models (issue 17, point 4) against closed forms
// and an independent integration. examples/single_track: the linear
// single-track model at constant speed, written as a bond graph. TyreRig.*:
// the `tyre` element on a test rig (models/tyre_rig.mbg) against the Magic
// Formula's equations written out here and the relaxation's closed form.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

std::string fmt_args(double v, double alpha0, double w) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "--set v=%.17g --set alpha0=%.17g --set w=%.17g", v, alpha0, w);
  return buf;
}

constexpr double m = 1500, Iz = 2500, lf = 1.2, lr = 1.5, Cf = 80000, Cr = 90000, L = lf + lr;
constexpr double K = m * (lr / Cf - lf / Cr) / L;  // understeer gradient, rad per m/s^2

/// The model's equations written by hand: m (v_y' + v r) = F_yf + F_yr,
/// Iz r' = lf F_yf - lr F_yr, with F_yf = Cf (delta - (v_y + lf r) / v) and
/// F_yr = -Cr (v_y - lr r) / v; state (v_y, r).
std::array<double, 2> rates(const std::array<double, 2>& y, double v, double delta) {
  const double Fyf = Cf * (delta - (y[0] + lf * y[1]) / v), Fyr = -Cr * (y[0] - lr * y[1]) / v;
  return {(Fyf + Fyr) / m - v * y[1], (lf * Fyf - lr * Fyr) / Iz};
}

SimRun run_at(double v, double delta, const std::string& tag, double t_end = 8) {
  SimRun r = run(SINGLE_TRACK_SIM, "--set v=" + std::to_string(v) + " --set delta=" + std::to_string(delta) +
                                       " --t-end " + std::to_string(t_end),
                 tag);
  EXPECT_EQ(r.status, 0) << r.log;
  return r;
}

TEST(SingleTrack, SteadyYawRateGainAndSideSlipAreTheClosedForms) {
  for (double v : {10.0, 20.0, 30.0}) {
    const double delta = 0.02;
    SimRun r = run_at(v, delta, "single_track_" + std::to_string(static_cast<int>(v)));
    const auto& last = r.csv.rows.back();
    const double gain = v / (L + K * v * v);                                   // r / delta
    const double slip = (lr - m * lf * v * v / (Cr * L)) / (L + K * v * v);    // beta / delta
    EXPECT_NEAR(last[r.csv.col("yaw_rate")], gain * delta, 1e-7 * gain * delta) << "v = " << v;
    EXPECT_NEAR(last[r.csv.col("beta")], slip * delta, 1e-7 * std::abs(slip * delta) + 1e-12) << "v = " << v;
    EXPECT_NEAR(last[r.csv.col("ay")], v * gain * delta, 1e-7 * v * gain * delta) << "v = " << v;
  }
}

/// The understeer gradient from the runs alone: at steady state
/// delta = L / R + K ay with 1/R = r / v, so K = (delta - L r / v) / ay.
TEST(SingleTrack, TheUndersteerGradientFromTheRunsIsTheFormulas) {
  for (double v : {15.0, 25.0}) {
    const double delta = 0.01;
    SimRun r = run_at(v, delta, "single_track_K_" + std::to_string(static_cast<int>(v)));
    const auto& last = r.csv.rows.back();
    const double yaw = last[r.csv.col("yaw_rate")], ay = last[r.csv.col("ay")];
    EXPECT_NEAR((delta - L * yaw / v) / ay, K, 1e-6 * K) << "v = " << v;
  }
}

/// The whole response to the steering step, against a hand-written RK4 of
/// the same two equations (1e-5 s steps).
TEST(SingleTrack, TheTransientIsAnIndependentIntegrations) {
  const double v = 20, delta = 0.02;
  SimRun r = run_at(v, delta, "single_track_transient", 2);
  std::array<double, 2> y{0, 0};
  double t = 0;
  const double h = 1e-5;
  for (const auto& row : r.csv.rows) {
    while (t < row[0] - h / 2) {
      y = rk4_step<2>(y, h, [&](const std::array<double, 2>& s) { return rates(s, v, delta); });
      t += h;
    }
    EXPECT_NEAR(row[r.csv.col("yaw_rate")], y[1], 1e-8) << "t = " << row[0];
    EXPECT_NEAR(row[r.csv.col("beta")], y[0] / v, 1e-9) << "t = " << row[0];
  }
}

}  // namespace

namespace {

// ---- the tyre element ------------------------------------------------------------------

/// The Magic Formula with the `tyre` element's default coefficients
/// (compiler/multibody/tyres.cpp), written here from the MF 5.2 equations
/// (no camber, no offsets: the default set has none).
struct MagicFormula {
  double FNOMIN = 4000, PCX1 = 1.65, PDX1 = 1.0, PEX1 = -0.5, PKX1 = 20;
  double PCY1 = 1.3, PDY1 = 1.0, PEY1 = -1.0, PKY1 = -15, PKY2 = 1.7;
  double RBX1 = 12, RBX2 = 10, RCX1 = 1, RBY1 = 7, RBY2 = 2.5, RCY1 = 1;

  static double shape(double B, double C, double D, double E, double x) {
    return D * std::sin(C * std::atan(B * x - E * (B * x - std::atan(B * x))));
  }
  /// Fx, Fy at load Fz, slip ratio kappa and slip angle alpha.
  std::array<double, 2> forces(double Fz, double kappa, double alpha) const {
    const double Dx = PDX1 * Fz, Kx = PKX1 * Fz, Bx = Kx / (PCX1 * Dx);
    const double Fx0 = shape(Bx, PCX1, Dx, PEX1, kappa);
    const double Dy = PDY1 * Fz, Ky = PKY1 * FNOMIN * std::sin(2 * std::atan(Fz / (PKY2 * FNOMIN))), By = Ky / (PCY1 * Dy);
    const double Fy0 = shape(By, PCY1, Dy, PEY1, alpha);
    const double Gx = std::cos(RCX1 * std::atan(RBX1 * std::cos(std::atan(RBX2 * kappa)) * alpha));
    const double Gy = std::cos(RCY1 * std::atan(RBY1 * std::cos(std::atan(RBY2 * alpha)) * kappa));
    return {Gx * Fx0, Gy * Fy0};
  }
};

constexpr double kR0 = 0.3, kKz = 2e5, kLoad = 400 * 9.81;

SimRun rig(double v, double alpha0, double w, const std::string& tag, const std::string& extra = "") {
  SimRun r = run(TYRE_RIG_SIM, fmt_args(v, alpha0, w) + extra, tag);
  EXPECT_EQ(r.status, 0) << r.log;
  return r;
}

}  // namespace

TEST(TyreRig, SteadyForcesAreTheMagicFormulasWithCombinedSlip) {
  // The rig drives the wheel at speed v with its heading alpha0 left of the
  // motion and its spin w: at steady state the lagged slips are the slips,
  // kappa = (r w - v cos alpha0) / (v cos alpha0) with the loaded radius r,
  // and the slip angle is -alpha0 (the wheel moves to the right of its heading).
  const MagicFormula mf;
  struct Case { double v, alpha0, w; };
  for (const Case c : {Case{20, 0.03, 66}, Case{20, 0.1, 60}, Case{15, -0.05, 56}, Case{25, 0.2, 95}, Case{20, 0, 70}, Case{10, 0.35, 40}}) {
    SimRun r = rig(c.v, c.alpha0, c.w, "tyre_rig_" + std::to_string(c.alpha0) + "_" + std::to_string(c.w));
    const auto& last = r.csv.rows.back();
    const double Fz = last[r.csv.col("Fz")];
    EXPECT_NEAR(Fz, kLoad, 1e-7 * kLoad);
    const double radius = kR0 - Fz / kKz, vx = c.v * std::cos(c.alpha0);
    const double kappa = (radius * c.w - vx) / vx, alpha = -c.alpha0;
    EXPECT_NEAR(last[r.csv.col("kappa")], kappa, 1e-9) << c.alpha0 << ", " << c.w;
    EXPECT_NEAR(last[r.csv.col("alpha")], alpha, 1e-9) << c.alpha0 << ", " << c.w;
    const auto f = mf.forces(Fz, kappa, alpha);
    EXPECT_NEAR(last[r.csv.col("Fx")], f[0], 1e-6 * kLoad) << c.alpha0 << ", " << c.w;
    EXPECT_NEAR(last[r.csv.col("Fy")], f[1], 1e-6 * kLoad) << c.alpha0 << ", " << c.w;
  }
}

TEST(TyreRig, TheSlipAngleLagsByTheRelaxationLength) {
  // At constant load and speed the lagged tan(alpha) obeys
  // sigma t' + |Vx| t = Vy from 0: t = (Vy / |Vx|) (1 - exp(-|Vx| s / sigma)),
  // a first-order lag over the distance rolled.
  const double v = 20, alpha0 = 0.05;
  SimRun r = rig(v, alpha0, 70, "tyre_rig_lag", " --t-end 0.2 --interval 0.002");
  const double sigma = r.csv.rows.front()[r.csv.col("sigma_alpha")];
  // the MF 5.2 form: PTY1 sin(2 atan(Fz / (PTY2 FNOMIN))) R0
  EXPECT_NEAR(sigma, 2.0 * std::sin(2 * std::atan(kLoad / (1.7 * 4000))) * kR0, 1e-12);
  const double vx = v * std::cos(alpha0), vy = -v * std::sin(alpha0);
  for (double t : {0.004, 0.01, 0.02, 0.05, 0.1}) {
    const double expected = std::atan(vy / vx * (1 - std::exp(-vx * t / sigma)));
    EXPECT_NEAR(r.csv.at(t, "alpha"), expected, 1e-9) << "t = " << t;
  }
}

TEST(TyreRig, AStandingWheelCarriesItsLoadAndNothingElse) {
  SimRun r = rig(0, 0.1, 0, "tyre_rig_standing", " --t-end 1");
  for (const auto& row : r.csv.rows) {
    EXPECT_NEAR(row[r.csv.col("Fz")], kLoad, 1e-9 * kLoad);
    EXPECT_EQ(row[r.csv.col("Fx")], 0.0);
    EXPECT_EQ(row[r.csv.col("Fy")], 0.0);
  }
}

// ---- examples/two_track: the 14-DOF vehicle on Magic Formula tyres ---------------------

namespace {

// vehicle.mbg's data
constexpr double kBody = 1400, kLf = 1.2, kLr = 1.5, kG = 9.81, kFront = 30 + 1 + 15, kRear = 30 + 15;

/// The tyres' cornering stiffness at load Fz (default coefficients: PKY1 = -15, PKY2 = 1.7, FNOMIN = 4000).
double cornering_stiffness(double Fz) { return 15 * 4000 * std::sin(2 * std::atan(Fz / (1.7 * 4000))); }

}  // namespace

TEST(TwoTrack, StaticWheelLoadsAreTheWeightDistribution) {
  // Standing: each tyre carries its corner's own weight and its share of the
  // body's by the lever arms, exactly (a statically determinate car), at
  // every row of 2 s.
  SimRun r = run(TWO_TRACK_SIM, "--set v0=0 --set delta=0 --t-end 2", "two_track_static");
  ASSERT_EQ(r.status, 0) << r.log;
  const double front = kBody * kG * kLr / (kLf + kLr) / 2 + kFront * kG, rear = kBody * kG * kLf / (kLf + kLr) / 2 + kRear * kG;
  for (const auto& row : r.csv.rows) {
    EXPECT_NEAR(row[r.csv.col("Fz_fl")], front, 1e-8 * front) << "t = " << row[0];
    EXPECT_NEAR(row[r.csv.col("Fz_fr")], front, 1e-8 * front) << "t = " << row[0];
    EXPECT_NEAR(row[r.csv.col("Fz_rl")], rear, 1e-8 * rear) << "t = " << row[0];
    EXPECT_NEAR(row[r.csv.col("Fz_rr")], rear, 1e-8 * rear) << "t = " << row[0];
  }
}

TEST(TwoTrack, AtLowLateralAccelerationTheYawRateIsTheSingleTrackModels) {
  // Steady-state circular driving at 20 m/s with 0.01 rad at the front
  // wheels (about 1.5 m/s^2): the yaw rate against the single-track model's
  // r = v delta / (L + K v^2), with each axle's cornering stiffness twice
  // its tyres' at their static load, and the whole vehicle's mass and centre
  // of mass. The issue asks for 2 %.
  const double v = 20, delta = 0.01;
  SimRun r = run(TWO_TRACK_SIM, "--set delta=0.01", "two_track_circle");
  ASSERT_EQ(r.status, 0) << r.log;
  const double L = kLf + kLr;
  const double Fz_f = kBody * kG * kLr / L / 2 + kFront * kG, Fz_r = kBody * kG * kLf / L / 2 + kRear * kG;
  const double Cf = 2 * cornering_stiffness(Fz_f), Cr = 2 * cornering_stiffness(Fz_r);
  const double m = kBody + 2 * kFront + 2 * kRear;
  const double x_cg = (2 * kFront * kLf - 2 * kRear * kLr) / m;  // the corners shift the centre of mass
  const double lf = kLf - x_cg, lr = kLr + x_cg;
  const double K = m * (lr / Cf - lf / Cr) / L;
  const double expected = v * delta / (L + K * v * v);
  const auto& last = r.csv.rows.back();
  const double yaw = last[r.csv.col("yaw_rate")];
  EXPECT_NEAR(yaw, expected, 0.02 * expected) << "measured +0.047 %: " << (yaw / expected - 1) * 100 << " %";
  EXPECT_LT(std::abs(last[r.csv.col("ay")]), 2.0) << "m/s^2: low lateral acceleration";
  // steady: the lateral acceleration is v r (to the speed controller's small deficit)
  EXPECT_NEAR(last[r.csv.col("ay")], last[r.csv.col("v")] * yaw * std::cos(last[r.csv.col("beta")]), 2e-3 * std::abs(v * yaw));
}

TEST(TwoTrackBump, TheEnergyBalanceHoldsOverTheBump) {
  // Over a 5 cm bump at 10 m/s (the front wheels leave the road): the
  // bodies' kinetic and potential energy and the springs' change by what the
  // road, the drive and the dampers exchange, to the integration error.
  SimRun r = run(TWO_TRACK_BUMP_SIM, "", "two_track_bump");
  ASSERT_EQ(r.status, 0) << r.log;
  const double exchanged = r.csv.max_abs("work_in");
  EXPECT_GT(exchanged, 500) << "J: the bump must shake the car";
  EXPECT_LT(r.csv.max_deviation("balance"), 1e-4) << "J of " << exchanged << " J exchanged; measured 2.7e-6 J";
  double least = 1e9;
  for (const auto& row : r.csv.rows) least = std::min(least, row[r.csv.col("Fz_fl")]);
  EXPECT_EQ(least, 0.0) << "the front wheel leaves the road over the bump";
}

TEST(TwoTrackFrame, TheFlexibleFramesDifferencesShrinkAsItStiffens) {
  // The ladder frame reduced by mbgc-reduce, steady circle at 4.2 m/s^2: the
  // steel frame twists, rolls more and moves load transfer to the front
  // (examples/two_track/README.md). Its differences from the
  // 1000-times-stiffer frame come from its compliance, so a frame 10 times
  // stiffer must show about a tenth of them.
  SimRun flex = run(TWO_TRACK_FRAME_SIM, "", "two_track_frame");
  SimRun x10 = run(TWO_TRACK_FRAME_SIM, "--set frame_stiffness=10", "two_track_frame_x10");
  SimRun stiff = run(TWO_TRACK_FRAME_SIM, "--set frame_stiffness=1000", "two_track_frame_stiff");
  for (const SimRun* r : {&flex, &x10, &stiff}) ASSERT_EQ(r->status, 0) << r->log;
  auto last = [](const SimRun& r, const char* col) { return r.csv.rows.back()[r.csv.col(col)]; };
  auto front_transfer = [&](const SimRun& r) { return (last(r, "Fz_fr") - last(r, "Fz_fl")) / 2; };
  EXPECT_GT(std::abs(last(flex, "twist")), 1e-4) << "rad: the steel frame twists";
  EXPECT_LT(std::abs(last(stiff, "twist")), 1e-6) << "rad: the stiff one barely";
  for (const char* out : {"roll", "twist", "yaw_rate"}) {
    const double d1 = last(flex, out) - last(stiff, out), d10 = last(x10, out) - last(stiff, out);
    EXPECT_NEAR(d1 / d10, 10, 2.5) << out << ": " << d1 << " and " << d10;
  }
  const double t1 = front_transfer(flex) - front_transfer(stiff), t10 = front_transfer(x10) - front_transfer(stiff);
  EXPECT_GT(t1, 0) << "N: the flexible frame moves load transfer to the front";
  EXPECT_NEAR(t1 / t10, 10, 2.5) << t1 << " and " << t10 << " N";
}

TEST(TwoTrack, TheNativeBuildGivesTheSameRunToRounding) {
  // mbgc_add_simulation(... NATIVE) compiles the car with -march=native: the
  // same equations, rounded differently where multiply-adds fuse. Over the
  // 8 s manoeuvre at a fixed step the outputs agree to 1e-9 of their peaks.
  SimRun portable = run(TWO_TRACK_SIM, "--solver rk4 --step 1e-3", "two_track_portable");
  SimRun native = run(TWO_TRACK_NATIVE_SIM, "--solver rk4 --step 1e-3", "two_track_native");
  ASSERT_EQ(portable.status, 0) << portable.log;
  ASSERT_EQ(native.status, 0) << native.log;
  ASSERT_EQ(portable.csv.header, native.csv.header);
  for (std::size_t c = 1; c < portable.csv.header.size(); ++c) {
    const std::string& name = portable.csv.header[c];
    EXPECT_LE(max_difference(portable.csv, native.csv, name), 1e-9 * std::max(portable.csv.max_abs(name), 1e-3)) << name;
  }
}
