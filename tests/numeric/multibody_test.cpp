// Numerical tests of the multibody examples (examples/pendulum,
// torque_free_body, double_pendulum_3d, chain): closed forms, conservation
// laws, constraint drift and an independent integration in joint coordinates.
// Every tolerance is stated with the value measured when it was set.
#include <gtest/gtest.h>

#include "sim_run.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

namespace {

using namespace numeric;

const double kG = 9.81;

/// The "constraint drift: position X" value from a run summary (NaN if absent).
double summary_position_drift(const std::string& log) {
  const std::string key = "constraint drift: position ";
  std::size_t at = log.find(key);
  if (at == std::string::npos) return NAN;
  return std::stod(log.substr(at + key.size()));
}

// ---- Jacobi elliptic functions by the arithmetic-geometric mean ---------------
// Abramowitz & Stegun 16.4: a0 = 1, b0 = k' = sqrt(1 - k^2), c0 = k;
// a_n = (a + b)/2, b_n = sqrt(a b), c_n = (a - b)/2 until c_N vanishes;
// phi_N = 2^N a_N u, phi_{n-1} = (phi_n + asin(c_n sin(phi_n) / a_n)) / 2;
// sn(u, k) = sin(phi_0). K(k) = pi / (2 a_N) (A&S 17.6).
struct Agm {
  std::array<double, 32> a{}, c{};
  int n = 0;
  explicit Agm(double k) {
    double b = std::sqrt(1 - k * k);
    a[0] = 1;
    c[0] = k;
    while (std::abs(c[n]) > 1e-17 && n + 1 < static_cast<int>(a.size())) {
      a[n + 1] = (a[n] + b) / 2;
      c[n + 1] = (a[n] - b) / 2;
      b = std::sqrt(a[n] * b);
      ++n;
    }
  }
  double K() const { return M_PI / (2 * a[n]); }
  double sn(double u) const {
    double phi = std::ldexp(a[n] * u, n);
    for (int i = n; i > 0; --i) phi = (phi + std::asin(c[i] * std::sin(phi) / a[i])) / 2;
    return std::sin(phi);
  }
};

double elliptic_K(double k) { return Agm(k).K(); }
double jacobi_sn(double u, double k) { return Agm(k).sn(u); }

/// Simple pendulum released from rest at theta0 (from the downward vertical):
/// theta(t) = 2 asin(k sn(K - omega0 t, k)), k = sin(theta0/2).
double pendulum_theta(double t, double theta0, double g, double L) {
  double k = std::sin(theta0 / 2);
  return 2 * std::asin(k * jacobi_sn(elliptic_K(k) - std::sqrt(g / L) * t, k));
}

TEST(EllipticSn, ReducesToSineForZeroModulus) {
  for (double u : {-2.0, -0.3, 0.0, 0.7, 1.5, 3.0, 10.0}) EXPECT_NEAR(jacobi_sn(u, 0), std::sin(u), 1e-15) << u;
  EXPECT_NEAR(elliptic_K(0), M_PI / 2, 1e-15);
}

TEST(EllipticSn, QuarterAndHalfPeriodValues) {
  for (double k : {0.1, 0.5, std::sin(M_PI / 4), 0.9, 0.99}) {
    double K = elliptic_K(k), kp = std::sqrt(1 - k * k);
    EXPECT_NEAR(jacobi_sn(K, k), 1, 1e-12) << k;
    EXPECT_NEAR(jacobi_sn(2 * K, k), 0, 1e-12) << k;
    EXPECT_NEAR(jacobi_sn(-K, k), -1, 1e-12) << k;
    EXPECT_NEAR(jacobi_sn(K / 2, k), 1 / std::sqrt(1 + kp), 1e-12) << k;  // A&S 16.5
  }
  // K(1/sqrt 2) = Gamma(1/4)^2 / (4 sqrt(pi)) (A&S 17.3.13's lemniscatic case)
  EXPECT_NEAR(elliptic_K(std::sqrt(0.5)), std::pow(std::tgamma(0.25), 2) / (4 * std::sqrt(M_PI)), 1e-14);
}

TEST(EllipticSn, SatisfiesItsDifferentialEquation) {
  // d sn/du = cn dn = sqrt(1 - sn^2) sqrt(1 - k^2 sn^2) for |u| < K (cn > 0 there)
  const double h = 1e-5;
  for (double k : {0.3, std::sin(M_PI / 4), 0.95}) {
    double K = elliptic_K(k);
    for (double f : {-0.9, -0.5, 0.0, 0.2, 0.6, 0.9}) {
      double u = f * K, s = jacobi_sn(u, k);
      double d = (jacobi_sn(u + h, k) - jacobi_sn(u - h, k)) / (2 * h);
      EXPECT_NEAR(d, std::sqrt(1 - s * s) * std::sqrt(1 - k * k * s * s), 1e-9) << k << " " << u;  // measured <= 3.2e-11
    }
  }
}

TEST(EllipticSn, PendulumClosedFormIsPeriodicAndConservesEnergy) {
  const double theta0 = M_PI / 2, g = kG, L = 1;
  const double period = 4 * elliptic_K(std::sin(theta0 / 2)) / std::sqrt(g / L);
  EXPECT_NEAR(pendulum_theta(0, theta0, g, L), theta0, 1e-12);
  EXPECT_NEAR(pendulum_theta(period / 4, theta0, g, L), 0, 1e-12);
  EXPECT_NEAR(pendulum_theta(period / 2, theta0, g, L), -theta0, 1e-12);
  EXPECT_NEAR(pendulum_theta(period, theta0, g, L), theta0, 1e-12);
  EXPECT_GT(pendulum_theta(0.1, theta0, g, L), 0.0);
  EXPECT_LT(pendulum_theta(0.1, theta0, g, L), theta0);  // swings down first
  // theta'^2 / 2 = (g/L)(cos theta - cos theta0) along the closed form
  const double h = 1e-5;
  for (double t : {0.3, 0.7, 1.0, 1.9, 3.1}) {
    double th = pendulum_theta(t, theta0, g, L);
    double w = (pendulum_theta(t + h, theta0, g, L) - pendulum_theta(t - h, theta0, g, L)) / (2 * h);
    EXPECT_NEAR(w * w / 2, g / L * (std::cos(th) - std::cos(theta0)), 1e-8) << t;  // measured <= 2.6e-9
  }
}

// ---- pendulum: a point mass on a distance constraint (lagrange, IDA) ----------
// examples/pendulum: m = 1 kg, L = 1 m, g = 9.81, released from (1, 0) at rest.
/// Runs a pendulum simulator to 10 s at rtol 1e-10 and checks x, y against
/// the elliptic closed form at t = 1, 2, 10 s (1e-6 m) and the release.
SimRun pendulum_against_closed_form(const std::string& sim, const std::string& tag) {
  SimRun r = run(sim, "--rtol 1e-10 --atol 1e-12 --interval 0.01 --t-end 10", tag);
  if (r.status != 0) {
    ADD_FAILURE() << r.log;
    return r;
  }
  const double L = 1;
  for (double t : {1.0, 2.0, 10.0}) {
    double th = pendulum_theta(t, M_PI / 2, kG, L);
    EXPECT_NEAR(r.csv.at(t, "x"), L * std::sin(th), 1e-6) << tag << ", t = " << t;
    EXPECT_NEAR(r.csv.at(t, "y"), -L * std::cos(th), 1e-6) << tag << ", t = " << t;
  }
  // the bob starts at (1, 0) and swings toward x decreasing, y negative
  EXPECT_NEAR(r.csv.at(0.0, "x"), 1.0, 1e-15);
  EXPECT_NEAR(r.csv.at(0.0, "y"), 0.0, 1e-15);
  EXPECT_LT(r.csv.at(0.1, "x"), 1.0);
  EXPECT_LT(r.csv.at(0.1, "y"), 0.0);
  return r;
}

TEST(MultibodyPendulum, PositionMatchesTheEllipticClosedForm) {
  pendulum_against_closed_form(MB_PENDULUM_SIM, "mb_pendulum_position");  // measured: largest error 1.5e-8 m (x at t = 10 s)
}

TEST(MultibodyPendulum, JointCoordinatesMatchTheEllipticClosedForm) {
  // the same model with --constraints coordinates: the rod's two direction
  // angles are the states, an ODE with nothing to drift; measured: largest
  // error 9.5e-9 m (x at t = 10 s)
  SimRun r = pendulum_against_closed_form(MB_PENDULUM_COORDINATES_SIM, "mb_pendulum_coordinates");
  ASSERT_EQ(r.status, 0);
  EXPECT_LT(r.csv.max_deviation("E") / (1 * kG * 1), 1e-8);  // measured 7.4e-9
  // the rod's tension is the centripetal force plus gravity's share: at the
  // bottom (x = 0) of a swing released horizontally F = 3 m g
  double bottom = 1e9, F = 0;
  for (const auto& row : r.csv.rows)
    if (std::abs(row[r.csv.col("x")]) < bottom) bottom = std::abs(row[r.csv.col("x")]), F = row[r.csv.col("F")];
  EXPECT_NEAR(F, 3 * kG, 0.01 * 3 * kG);  // the nearest 10 ms row is within 1 % of the bottom
}

TEST(MultibodyPendulum, ConservesEnergyAndHoldsTheConstraint) {
  std::string report = work_file("mb_pendulum_constraints", ".csv");
  std::remove(report.c_str());
  SimRun r = run(MB_PENDULUM_SIM, "--rtol 1e-10 --atol 1e-12 --constraint-report \"" + report + "\"", "mb_pendulum_energy");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 1001u);
  // E(0) = 0 (potential energy is zero at the pivot's height): relative to
  // m g L = 9.81 J, the energy turned into motion at the bottom. Measured 2.0e-9.
  EXPECT_LT(r.csv.max_deviation("E") / (1 * kG * 1), 1e-8);
  double drift = summary_position_drift(r.log);
  EXPECT_LT(drift, 1e-8) << r.log;  // measured 3.8e-11 m
  Csv c = read_csv(report);
  ASSERT_EQ(c.rows.size(), r.csv.rows.size()) << "one report row per output time";
  EXPECT_LT(c.max_abs("max_abs_g"), 1e-8);     // measured 3.8e-11 m
  EXPECT_LT(c.max_abs("max_abs_gdot"), 1e-8);  // measured 2.9e-10 m/s
}

// ---- torque-free body spinning about its intermediate axis ------------------
// examples/torque_free_body: inertia diag(1, 2, 3), omega0 = (0, 1, 0.01).
TEST(TorqueFreeBody, ConservesEnergyAndAngularMomentumWhileTumbling) {
  SimRun r = run(TORQUE_FREE_SIM, "--t-end 100", "torque_free_body");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 2001u);
  const Csv& c = r.csv;
  double E0 = c.rows.front()[c.col("E")];
  EXPECT_NEAR(E0, 0.5 * (2 * 1 * 1 + 3 * 0.01 * 0.01), 1e-15);
  EXPECT_LT(c.max_deviation("E") / E0, 1e-8);  // measured 6.9e-11
  double H0 = std::hypot(c.rows.front()[c.col("Hx")], c.rows.front()[c.col("Hy")], c.rows.front()[c.col("Hz")]);
  EXPECT_NEAR(H0, std::hypot(2.0, 0.03), 1e-15);
  for (const char* h : {"Hx", "Hy", "Hz"}) EXPECT_LT(c.max_deviation(h) / H0, 1e-8) << h;  // measured <= 6.3e-11
  // |I omega| (body frame) = |H| (inertial frame) at every row: the attitude
  // that turns one into the other stays a rotation
  double worst = 0;
  for (const auto& row : c.rows) {
    double Iw = std::hypot(1 * row[c.col("wx")], 2 * row[c.col("wy")], 3 * row[c.col("wz")]);
    worst = std::max(worst, std::abs(Iw - H0) / H0);
  }
  EXPECT_LT(worst, 1e-8);
  // the intermediate axis is unstable: omega_y reverses (first at ~9.45 s, five times in 100 s)
  std::size_t wy = c.col("wy");
  int reversals = 0;
  for (std::size_t i = 1; i < c.rows.size(); ++i)
    if (c.rows[i - 1][wy] * c.rows[i][wy] < 0) ++reversals;
  EXPECT_GE(reversals, 1);
}

// ---- 3-D double pendulum: revolute + spherical joints (lagrange, IDA) ---------
TEST(DoublePendulum3d, ConservesEnergyHoldsConstraintsAndLeavesThePlane) {
  std::string report = work_file("double_pendulum_3d_constraints", ".csv");
  std::remove(report.c_str());
  // the model's own tolerances (rtol 1e-8, atol 1e-10): no tightening needed
  SimRun r = run(DOUBLE_PENDULUM_3D_SIM, "--constraint-report \"" + report + "\"", "double_pendulum_3d");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 501u);
  // E(0) = 0 (both rods horizontal at rest): relative to 2 m g l = 9.81 J, the
  // potential energy released when both hang straight down. Measured 5.3e-7
  // (5.9e-9 at rtol 1e-10).
  const double m = 1, l = 0.5;
  EXPECT_LT(r.csv.max_deviation("E") / (2 * m * kG * l), 1e-6);
  EXPECT_LT(summary_position_drift(r.log), 1e-7) << r.log;  // measured 2.8e-10 m
  Csv c = read_csv(report);
  ASSERT_EQ(c.rows.size(), r.csv.rows.size());
  EXPECT_LT(c.max_abs("max_abs_g"), 1e-7);     // measured 2.8e-10
  EXPECT_LT(c.max_abs("max_abs_gdot"), 1e-7);  // measured 3.1e-8
  // Rod 2's tip starts off the x-z plane (y = l sin 0.5 = 0.2397 m). A motion
  // confined to the hinge's plane (rod 2 rigid with rod 1) keeps that y; the
  // ball joint's 3-D motion moves it (measured: y from -0.500 to 0.323 m).
  EXPECT_NEAR(r.csv.at(0.0, "y"), l * std::sin(0.5), 1e-12);
  EXPECT_GT(r.csv.max_abs("y"), 0.01);  // true from t = 0 on: the real check is the next one
  std::size_t y = r.csv.col("y");
  double moved = 0;
  for (const auto& row : r.csv.rows) moved = std::max(moved, std::abs(row[y] - r.csv.rows.front()[y]));
  EXPECT_GT(moved, 0.01);
}

// ---- chain of rods: against a hand-written double pendulum ----
// Two uniform rods (l = 0.5 m, m = 1 kg, I = m l^2/12 about the centre),
// joint angles q1 (rod 1 from the downward vertical) and q2 (rod 2 relative
// to rod 1). With absolute angles th1 = q1, th2 = q1 + q2 the Lagrange equations are
//   [4/3 m l^2       m l^2/2 c ] [th1'']   [-m l^2/2 s th2'^2 - 3/2 m g l sin th1]
//   [m l^2/2 c       m l^2/3   ] [th2''] = [ m l^2/2 s th1'^2 - 1/2 m g l sin th2]
// with c = cos(th1 - th2), s = sin(th1 - th2); in the joint coordinates
// q = (q1, q2), th = J q with J = [[1, 0], [1, 1]] constant, so
// M_q = J^T M J and f_q = J^T f: M_q(q) q'' = f_q(q, q').
std::array<double, 4> double_pendulum_rates(const std::array<double, 4>& y) {
  const double m = 1, l = 0.5, g = kG;
  const double q1 = y[0], q2 = y[1], u1 = y[2], u2 = y[3];  // u = q'
  const double c = std::cos(q2), s = -std::sin(q2);           // cos, sin of th1 - th2 = -q2
  const double M11 = 4.0 / 3 * m * l * l, M12 = m * l * l / 2 * c, M22 = m * l * l / 3;
  const double f1 = -m * l * l / 2 * s * (u1 + u2) * (u1 + u2) - 1.5 * m * g * l * std::sin(q1);
  const double f2 = m * l * l / 2 * s * u1 * u1 - 0.5 * m * g * l * std::sin(q1 + q2);
  const double A = M11 + 2 * M12 + M22, B = M12 + M22, C = M22;  // M_q = J^T M J
  const double r1 = f1 + f2, r2 = f2;                             // f_q = J^T f
  const double det = A * C - B * B;
  return {u1, u2, (C * r1 - B * r2) / det, (A * r2 - B * r1) / det};
}

/// q1, q2 at time T from rest at (0.3, 0.3): classical RK4 with a 1e-5 s step.
std::array<double, 2> double_pendulum_reference(double T) {
  std::array<double, 4> y{0.3, 0.3, 0, 0};
  const double dt = 1e-5;
  const long steps = std::lround(T / dt);
  for (long n = 0; n < steps; ++n) y = rk4_step(y, dt, double_pendulum_rates);
  return {y[0], y[1]};
}

TEST(DoublePendulumReference, ConservesEnergy) {
  // the hand-written reference on its own: T + V constant along the RK4 solution
  const double m = 1, l = 0.5, g = kG;
  auto energy = [&](const std::array<double, 4>& y) {
    double th1 = y[0], th2 = y[0] + y[1], w1 = y[2], w2 = y[2] + y[3];
    double T = 0.5 * (4.0 / 3 * m * l * l) * w1 * w1 + 0.5 * (m * l * l / 3) * w2 * w2 +
               m * l * l / 2 * std::cos(th1 - th2) * w1 * w2;
    double V = -m * g * l / 2 * std::cos(th1) - m * g * (l * std::cos(th1) + l / 2 * std::cos(th2));
    return T + V;
  };
  std::array<double, 4> y{0.3, 0.3, 0, 0};
  const double E0 = energy(y), dt = 1e-5;
  double worst = 0;
  for (int n = 0; n < 100000; ++n) {
    y = rk4_step(y, dt, double_pendulum_rates);
    worst = std::max(worst, std::abs(energy(y) - E0));
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(std::abs(y[0] - 0.3), 0.1);  // it moved
}

TEST(ChainLagrange, TwoRodsMatchTheJointCoordinateDoublePendulum) {
  // Multipliers (GGL index-2 DAE, IDA) satisfy the joints to the integrator's
  // tolerance, so the only difference is integration error. Measured at t = 1 s,
  // model tolerances (rtol 1e-8, atol 1e-10): q1 1.7e-10, q2 1.3e-8 rad. Tolerance 1e-6
  // rad, the joint-angle accuracy the chain benchmark asks for.
  const std::array<double, 2> ref = double_pendulum_reference(1.0);
  SimRun r = run(CHAIN2_SIM, "", "chain_2");
  ASSERT_EQ(r.status, 0) << r.log;
  EXPECT_NEAR(r.csv.at(0.0, "q1"), 0.3, 1e-12);
  EXPECT_NEAR(r.csv.at(0.0, "q2"), 0.3, 1e-12);
  EXPECT_NEAR(r.csv.at(1.0, "q1"), ref[0], 1e-6);
  EXPECT_NEAR(r.csv.at(1.0, "q2"), ref[1], 1e-6);
}

TEST(ChainPenalty, TwoRodsMatchTheJointCoordinateDoublePendulum) {
  const std::array<double, 2> ref = double_pendulum_reference(1.0);  // (-0.23540990, -0.27568137)
  SimRun r = run(CHAIN2_PENALTY_SIM, "", "chain_2_penalty");
  ASSERT_EQ(r.status, 0) << r.log;
  EXPECT_NEAR(r.csv.at(0.0, "q1"), 0.3, 1e-12);
  EXPECT_NEAR(r.csv.at(0.0, "q2"), 0.3, 1e-12);
  // Penalty joints (default stiffness 1e6 m N/m, critically damped) stretch by
  // ~force/k = 2e-5 m. Measured difference at t = 1 s, model tolerances
  // (rtol 1e-8): q1 6.4e-6 rad, q2 8.1e-5 rad. Tolerance 2.5e-4 rad (~3x).
  double d1 = std::abs(r.csv.at(1.0, "q1") - ref[0]), d2 = std::abs(r.csv.at(1.0, "q2") - ref[1]);
  EXPECT_LT(d1, 2.5e-4);
  EXPECT_LT(d2, 2.5e-4);
  // A 100x stiffer penalty (set at run time) brings it 100x closer: the
  // difference is the penalty's compliance, not a modelling error. Measured at
  // k = 1e8, rtol 1e-10: q1 5.8e-8, q2 8.1e-7 rad (k = 1e7: 6.5e-7, 8.2e-6).
  // rtol 1e-10 because at 1e-8 the integration error (~4e-6) hides the penalty's.
  // atol 1e-11 (a velocity: each momentum's tolerance is atol x its inertia,
  // 0.021 kg m^2 for a rod's spin): at 1e-12 the rods' angular momenta were
  // held to 2e-14 kg m^2/s, below the rounding noise of 1e8 N/m springs, and
  // IDA stopped at t = 0.129 s with 10258 failed error tests.
  SimRun s = run(CHAIN2_PENALTY_SIM, "--set j1.stiffness=1e8 --set j2.stiffness=1e8 --rtol 1e-10 --atol 1e-11", "chain_2_stiff");
  ASSERT_EQ(s.status, 0) << s.log;
  double s1 = std::abs(s.csv.at(1.0, "q1") - ref[0]), s2 = std::abs(s.csv.at(1.0, "q2") - ref[1]);
  EXPECT_LT(s1, 2.5e-6);
  EXPECT_LT(s2, 2.5e-6);
  EXPECT_LT(std::max(s1, s2), std::max(d1, d2) / 30);
}

TEST(ChainLagrange, EightRodsRun) {
  // chain_8: the same model compiled with --set N=8: one joint angle per rod
  SimRun r = run(CHAIN8_SIM, "", "chain_8");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.header.size(), 9u);
  for (int i = 1; i <= 8; ++i) {
    std::string q = "q" + std::to_string(i);
    EXPECT_NEAR(r.csv.at(0.0, q), 0.3, 1e-12) << q;
    for (const auto& row : r.csv.rows) ASSERT_TRUE(std::isfinite(row[r.csv.col(q)])) << q;
  }
  EXPECT_GT(std::abs(r.csv.at(1.0, "q1") - 0.3), 0.1);  // it moved (measured q1(1 s) = 0.137)
}

// ---- joint coordinates (mbgc --constraints coordinates) ----
TEST(ChainCoordinates, TwoRodsMatchTheJointCoordinateDoublePendulum) {
  // The same chain model with the joints' angles and rates as states: an ODE
  // whose accelerations come from the mass-matrix system reduce builds from
  // the bodies' derivative causality. Nothing constrains anything, so the only
  // difference to the reference is integration error, with an implicit (IDA,
  // the model's) and an explicit (dopri5) integrator alike.
  const std::array<double, 2> ref = double_pendulum_reference(1.0);
  for (const char* solver : {"ida", "dopri5"}) {
    SimRun r = run(CHAIN2_COORDINATES_SIM, std::string("--solver ") + solver, std::string("chain_2_coordinates_") + solver);
    ASSERT_EQ(r.status, 0) << r.log;
    EXPECT_EQ(r.log.find("constraint"), std::string::npos) << "no constraint rows: " << r.log;
    EXPECT_NEAR(r.csv.at(0.0, "q1"), 0.3, 1e-15);
    EXPECT_NEAR(r.csv.at(0.0, "q2"), 0.3, 1e-15);
    // measured at rtol 1e-8: ida q1 1.5e-9, q2 1.5e-9; dopri5 1.8e-10, 5.4e-10
    EXPECT_NEAR(r.csv.at(1.0, "q1"), ref[0], 1e-6) << solver;
    EXPECT_NEAR(r.csv.at(1.0, "q2"), ref[1], 1e-6) << solver;
  }
}

TEST(DoublePendulum3dCoordinates, AgreesWithMultipliersAndConservesEnergy) {
  // A hinge and a ball joint: the hinge angle and the ball's relative
  // quaternion and angular velocity are the states. Both runs at rtol 1e-10
  // over 5 s; measured: the tip 5.6e-8 m apart, energy drift 5.7e-8 J.
  const std::string tol = "--rtol 1e-10 --atol 1e-12";
  SimRun a = run(DOUBLE_PENDULUM_3D_SIM, tol, "double_pendulum_3d_tight");
  SimRun b = run(DOUBLE_PENDULUM_3D_COORDINATES_SIM, tol, "double_pendulum_3d_coordinates");
  ASSERT_EQ(a.status, 0) << a.log;
  ASSERT_EQ(b.status, 0) << b.log;
  ASSERT_EQ(a.csv.rows.size(), b.csv.rows.size());
  double tip = 0, energy = 0;
  for (std::size_t k = 0; k < a.csv.rows.size(); ++k) {
    for (const char* c : {"x", "y", "z"})
      tip = std::max(tip, std::abs(a.csv.rows[k][a.csv.col(c)] - b.csv.rows[k][b.csv.col(c)]));
    energy = std::max(energy, std::abs(b.csv.rows[k][b.csv.col("E")] - b.csv.rows[0][b.csv.col("E")]));
  }
  EXPECT_LT(tip, 1e-6);
  EXPECT_LT(energy, 1e-6);
}

/// Largest difference of every q column between two runs of the chain.
double chain_difference(const SimRun& a, const SimRun& b, int n) {
  double worst = 0;
  for (std::size_t k = 0; k < a.csv.rows.size(); ++k)
    for (int i = 1; i <= n; ++i) {
      std::string q = "q" + std::to_string(i);
      worst = std::max(worst, std::abs(a.csv.rows[k][a.csv.col(q)] - b.csv.rows[k][b.csv.col(q)]));
    }
  return worst;
}

TEST(ChainCoordinates, EightAndThirtyTwoRodsAgreeWithMultipliers) {
  // Two formulations of one model, both integrated at rtol 1e-10: the angles
  // agree over 1 s to 1e-6 rad (the chain benchmark's accuracy); measured
  // 1.5e-9 rad for 32 rods.
  for (auto [n, lagrange, coordinates] : {std::tuple{8, CHAIN8_SIM, CHAIN8_COORDINATES_SIM},
                                          std::tuple{32, CHAIN32_SIM, CHAIN32_COORDINATES_SIM}}) {
    const std::string tol = "--rtol 1e-10 --atol 1e-12";
    SimRun a = run(lagrange, tol, "chain_" + std::to_string(n) + "_lagrange_tight");
    SimRun b = run(coordinates, tol, "chain_" + std::to_string(n) + "_coordinates_tight");
    ASSERT_EQ(a.status, 0) << a.log;
    ASSERT_EQ(b.status, 0) << b.log;
    ASSERT_EQ(a.csv.rows.size(), b.csv.rows.size());
    ASSERT_EQ(b.csv.header.size(), static_cast<std::size_t>(n + 1));
    EXPECT_LT(chain_difference(a, b, n), 1e-6) << n << " rods";
    EXPECT_GT(std::abs(b.csv.at(1.0, "q1") - 0.3), 0.03) << "it moved";  // measured: 0.16 (8 rods), 0.059 (32)
  }
}

TEST(PlanarBelowAMovingBody, CoordinatesAgreeWithMultipliers) {
  // models/planar_below_moving.mbg: mbgc stopped on it in joint coordinates
  // (an internal error, found by tests/random). Both runs at rtol 1e-10,
  // atol 1e-12; measured 3.6e-9 m apart over 2 s while the lower body falls
  // 15.7 m sliding down its plane.
  SimRun a = run(PLANAR_LAGRANGE_SIM, "", "planar_lagrange");
  SimRun b = run(PLANAR_COORDINATES_SIM, "", "planar_coordinates");
  ASSERT_EQ(a.status, 0) << a.log;
  ASSERT_EQ(b.status, 0) << b.log;
  ASSERT_EQ(a.csv.rows.size(), b.csv.rows.size());
  double apart = 0;
  for (std::size_t k = 0; k < a.csv.rows.size(); ++k)
    for (const char* c : {"x", "y", "z", "ux", "uy", "uz"})
      apart = std::max(apart, std::abs(a.csv.rows[k][a.csv.col(c)] - b.csv.rows[k][b.csv.col(c)]));
  EXPECT_LT(apart, 1e-7);
  EXPECT_GT(std::abs(b.csv.at(2.0, "z") - b.csv.at(0.0, "z")), 10.0);  // it slid down its plane
}

TEST(TreeCoordinates, EveryCoordinateJointAgreesWithMultipliersAndConservesEnergy) {
  // A spatial tree with every joint that has coordinates: revolute (torsion
  // spring), prismatic (spring), cylindrical, screw and fixed on one branch,
  // universal, planar and spherical on the other, under oblique gravity,
  // integrated with multipliers and in joint coordinates (both rtol 1e-10,
  // atol 1e-12). Over the first second (the multiplier run stalls near 1.8 s
  // as the sleeve slides off), measured: coordinates 1.1e-9 rad, positions
  // 7.7e-10 m apart; energy drift in coordinates 1.1e-7 J of 24.9 J over 2 s.
  SimRun a = run(TREE_LAGRANGE_SIM, "--t-end 1", "tree_lagrange");
  SimRun b = run(TREE_COORDINATES_SIM, "", "tree_coordinates");
  ASSERT_EQ(a.status, 0) << a.log;
  ASSERT_EQ(b.status, 0) << b.log;
  double angles = 0, lengths = 0;
  for (std::size_t k = 0; k < a.csv.rows.size(); ++k) {
    for (const char* c : {"hinge_angle", "sleeve_angle", "thread_angle"}) {
      double d = a.csv.rows[k][a.csv.col(c)] - b.csv.rows[k][b.csv.col(c)];
      d = std::remainder(d, 2 * std::acos(-1.0));  // the multiplier run reads angles with atan2
      angles = std::max(angles, std::abs(d));
    }
    for (const char* c : {"slide_d", "sleeve_d", "x", "y", "z", "bx", "by", "bz"})
      lengths = std::max(lengths, std::abs(a.csv.rows[k][a.csv.col(c)] - b.csv.rows[k][b.csv.col(c)]));
  }
  EXPECT_LT(angles, 1e-7);
  EXPECT_LT(lengths, 1e-7);
  const double E0 = b.csv.at(0.0, "E");
  double drift = 0, moved = 0;
  for (const auto& row : b.csv.rows) {
    drift = std::max(drift, std::abs(row[b.csv.col("E")] - E0));
    moved = std::max(moved, std::abs(row[b.csv.col("sleeve_d")] - 0.05));
  }
  EXPECT_LT(drift, 1e-6);
  EXPECT_GT(moved, 0.5);  // the sleeve slid
  EXPECT_GT(std::abs(b.csv.at(2.0, "by") - b.csv.at(0.0, "by")), 1.0);  // the puck slid down its plane
}

TEST(ForcedArmCoordinates, ForceElementsMomentumAndReactionsAgreeWithMultipliers) {
  // Bodies moved by joint coordinates keep their translational junction in
  // body axes; force elements, momentum, kinetic energy, point velocities and
  // joint reactions are turned to world axes. Both runs at rtol 1e-10, atol
  // 1e-12 over 2 s; measured: motion within 4.5e-10, spring force within
  // 1.8e-9 N, the spherical joint's reaction (from IDA's multipliers) within
  // 1.7e-7 N.
  SimRun a = run(FORCED_ARM_LAGRANGE_SIM, "", "forced_arm_lagrange");
  SimRun b = run(FORCED_ARM_COORDINATES_SIM, "--solver cvode", "forced_arm_coordinates");
  ASSERT_EQ(a.status, 0) << a.log;
  ASSERT_EQ(b.status, 0) << b.log;
  ASSERT_EQ(a.csv.rows.size(), b.csv.rows.size());
  auto worst = [&](const char* c) {
    double d = 0;
    for (std::size_t k = 0; k < a.csv.rows.size(); ++k)
      d = std::max(d, std::abs(a.csv.rows[k][a.csv.col(c)] - b.csv.rows[k][b.csv.col(c)]));
    return d;
  };
  for (const char* c : {"a", "hx", "hz", "vz", "tipz", "px", "KE"}) EXPECT_LT(worst(c), 1e-8) << c;
  EXPECT_LT(worst("Fsp"), 1e-7);
  EXPECT_LT(worst("jf"), 1e-5);
  EXPECT_GT(std::abs(b.csv.at(2.0, "hz") - b.csv.at(0.0, "hz")), 0.01);  // the push moved the hand out of plane
}

// ---- force elements: a spring to ground and an applied force at a point ----
TEST(ForceElements, SpringAndAppliedForceMatchTheirClosedForms) {
  SimRun r = run(FORCE_ELEMENTS_SIM, "--interval 0.01", "force_elements");
  ASSERT_EQ(r.status, 0) << r.log;
  const double k = 100, m = 1, w = std::sqrt(k / m), L0 = 1;
  double spring = 0, centre = 0, yaw = 0;
  for (const auto& row : r.csv.rows) {
    const double t = row[r.csv.col("t")];
    const double y = -L0 - kG / (w * w) * (1 - std::cos(w * t));
    spring = std::max(spring, std::abs(row[r.csv.col("y")] - y));
    EXPECT_NEAR(row[r.csv.col("F")], k * (row[r.csv.col("L")] - L0), 1e-9);  // on the bob, upwards when stretched
    centre = std::max(centre, std::abs(row[r.csv.col("vx")] - 0.5 * t));     // F / m = 1 N / 2 kg
    // theta'' = -cos(theta) (F r / J = 1) from rest: theta'^2 / 2 = -sin(theta)
    const double wz = row[r.csv.col("wz")], th = row[r.csv.col("th")];
    yaw = std::max(yaw, std::abs(0.5 * wz * wz + std::sin(th)));
  }
  // Measured at the model's rtol 1e-10: spring 5.8e-9 m (integration error:
  // 4.3e-7 at rtol 1e-8, 1.7e-10 at 1e-12), centre 0, yaw 5.1e-13.
  EXPECT_LT(spring, 2e-8);
  EXPECT_LT(centre, 1e-10);
  EXPECT_LT(yaw, 1e-8);
  EXPECT_LT(r.csv.at(1.0, "wz"), -0.9);  // it turned (clockwise: the force pulls the top of the rim along +x)
}

TEST(FreeJoint, AFloatingBaseCarryingAnArmKeepsItsMomentaAndItsCentreFliesStraight) {
  // models/floating_base.mbg: the base carries an arm, so its velocity
  // states are in its own axes, turned into the translation by its
  // rotation. It starts where its settings say (r0, v0 in world axes, w0 in
  // its own), and with no gravity the momenta and the energy hold and the
  // centre of mass moves at the momentum's velocity. Measured at rtol 1e-11:
  // momenta 6e-10, angular momentum 4e-9, energy 1.4e-9, the line 1.5e-10.
  auto r = run(FLOATING_BASE_SIM, "", "floating_base");
  ASSERT_EQ(r.status, 0) << r.log;
  const double r0[3] = {1, 2, 3}, v0[3] = {0.5, -1, 2}, w0[3] = {0.3, -0.5, 1.2};
  for (int i = 0; i < 3; ++i) {
    const std::string k = "[" + std::to_string(i + 1) + "]";
    EXPECT_NEAR(r.csv.at(0, "base_position" + k), r0[i], 1e-14);
    EXPECT_NEAR(r.csv.at(0, "base_velocity" + k), v0[i], 1e-14);
    EXPECT_NEAR(r.csv.at(0, "base_omega" + k), w0[i], 1e-14);
    EXPECT_LT(r.csv.max_deviation("momentum" + k), 5e-9) << "of 8 kg m/s";
    EXPECT_LT(r.csv.max_deviation("angular_momentum" + k), 5e-8) << "of 28 kg m^2/s";
    const double c0 = r.csv.at(0, "centre" + k), p = r.csv.at(0, "momentum" + k);
    double line = 0;
    for (const auto& row : r.csv.rows) line = std::max(line, std::abs(row[r.csv.col("centre" + k)] - (c0 + p / 4 * row[0])));
    EXPECT_LT(line, 5e-9) << "m: the centre of mass off its line (total mass 4 kg)";
  }
  EXPECT_GT(r.csv.max_deviation("base_omega[1]"), 0.1) << "the base must tumble";
  EXPECT_LT(r.csv.max_deviation("energy"), 2e-8) << "J of 10.9 J";
}

TEST(FreeJoint, AThrownBoxFliesItsParabolaAndKeepsItsAngularMomentum) {
  // models/free_body.mbg: six joint coordinates from ground. The centre flies
  // r0 + v0 t + g t^2 / 2 exactly; spun mostly about its intermediate axis the
  // box tumbles, and its angular momentum (world axes) and energy hold.
  auto r = run(FREE_BODY_SIM, "", "free_body");
  ASSERT_EQ(r.status, 0) << r.log;
  const double r0[3] = {1, 2, 3}, v0[3] = {3, -1, 8}, g[3] = {0, 0, -9.81};
  for (const auto& row : r.csv.rows) {
    const double t = row[0];
    for (int i = 0; i < 3; ++i) {
      const std::string col = "position[" + std::to_string(i + 1) + "]";
      EXPECT_NEAR(row[r.csv.col(col)], r0[i] + v0[i] * t + g[i] * t * t / 2, 1e-9) << col << " at t = " << t;
    }
  }
  for (const char* h : {"angular_momentum[1]", "angular_momentum[2]", "angular_momentum[3]"})
    EXPECT_LT(r.csv.max_deviation(h), 1e-8) << h << "; measured 3e-10 of 1.2 kg m^2/s";
  EXPECT_LT(r.csv.max_deviation("energy"), 1e-7) << "J of 136 J; measured 1.2e-9";
}

}  // namespace
