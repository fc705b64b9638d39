// vehicle_test.cpp — vehicle models (issue 17, point 4) against closed forms
// and an independent integration. examples/single_track: the linear
// single-track model at constant speed, written as a bond graph.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

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
