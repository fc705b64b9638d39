// Numerical regression tests: each runs a generated simulator and checks its
// CSV against an independent reference. Tolerances are stated per test.
#include <gtest/gtest.h>

#include "sim_run.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>
#include <array>
#include <algorithm>
#include <sys/wait.h>

namespace {

using namespace numeric;

// ---- DC motor: closed form of a linear 2x2 system with a step input ----------
// x = [i, omega], x' = A x + b V, x(0) = 0  =>  x(t) = A^-1 (e^{At} - I) b V,
// with e^{At} from the eigen-decomposition of A.
Eigen::Vector2d dc_motor_closed_form(double t, double V) {
  const double R = 0.4, L = 0.05, K = 0.678, J = 0.57207, D = 0.226;
  Eigen::Matrix2d A;
  A << -R / L, -K / L, K / J, -D / J;
  Eigen::Vector2d b(V / L, 0.0);
  Eigen::EigenSolver<Eigen::Matrix2d> es(A);
  Eigen::Matrix2cd V_ = es.eigenvectors();
  Eigen::Vector2cd lambda = es.eigenvalues();
  Eigen::Matrix2cd expAt = V_ * Eigen::Vector2cd(std::exp(lambda(0) * t), std::exp(lambda(1) * t)).asDiagonal() * V_.inverse();
  Eigen::Matrix2d E = expAt.real() - Eigen::Matrix2d::Identity();
  return A.fullPivLu().solve(E * b);
}

TEST(DcMotor, OmegaAndCurrentMatchClosedFormAtOneSecond) {
  SimRun r = run(DC_MOTOR_SIM, "", "dc_motor_default");
  ASSERT_EQ(r.status, 0) << r.log;
  // CVODE uses the Jacobian mbgc generated, not finite differences.
  EXPECT_NE(r.log.find("generated Jacobian"), std::string::npos) << r.log;
  Eigen::Vector2d ref = dc_motor_closed_form(1.0, 60.0);
  EXPECT_LT(rel_err(r.csv.at(1.0, "omega"), ref(1)), 1e-6) << r.csv.at(1.0, "omega") << " vs " << ref(1);
  EXPECT_LT(rel_err(r.csv.at(1.0, "current"), ref(0)), 1e-6) << r.csv.at(1.0, "current") << " vs " << ref(0);
}

TEST(DcMotor, EverySolverMatchesClosedForm) {
  Eigen::Vector2d ref = dc_motor_closed_form(1.0, 60.0);
  for (const char* args : {"--solver dopri5 --rtol 1e-10 --atol 1e-12", "--solver rk4 --step 1e-4",
                           "--solver ida --rtol 1e-10 --atol 1e-12"}) {
    SimRun r = run(DC_MOTOR_SIM, std::string(args) + " --t-end 1", "dc_motor_solver");
    ASSERT_EQ(r.status, 0) << args << "\n" << r.log;
    EXPECT_LT(rel_err(r.csv.at(1.0, "omega"), ref(1)), 1e-6) << args;
  }
}

TEST(DcMotor, ParameterOverrideScalesTheLinearResponse) {
  SimRun r = run(DC_MOTOR_SIM, "--set V_supply=30 --t-end 1", "dc_motor_30V");
  ASSERT_EQ(r.status, 0) << r.log;
  EXPECT_LT(rel_err(r.csv.at(1.0, "omega"), dc_motor_closed_form(1.0, 30.0)(1)), 1e-6);
}

// ---- quarter car: the same linear ODE, written by hand and integrated with a
// fine fixed-step RK4 (independent of mbgc and of SUNDIALS) -------------------
TEST(QuarterCar, MatchesIndependentIntegrationOfTheSameOde) {
  const double ms = 250, mu = 35, ks = 16000, cs = 1000, kt = 160000, h = 0.03, T = 2.0 / 10, t0 = 0.1;
  auto road_v = [&](double t) {
    return (t >= t0 && t < t0 + T) ? h * M_PI / T * std::sin(2 * M_PI * (t - t0) / T) : 0.0;
  };
  // y = [z_s, z_u, v_s, v_u, z_r]
  auto f = [&](double t, const std::array<double, 5>& y) {
    double fs = ks * (y[1] - y[0]) + cs * (y[3] - y[2]);
    double ft = kt * (y[4] - y[1]);
    return std::array<double, 5>{y[2], y[3], fs / ms, (ft - fs) / mu, road_v(t)};
  };
  SimRun r = run(QUARTER_CAR_SIM, "--interval 0.01", "quarter_car");
  ASSERT_EQ(r.status, 0) << r.log;
  std::array<double, 5> y{};
  const double dt = 1e-6;
  double t = 0;
  double worst = 0;
  for (const auto& row : r.csv.rows) {
    while (t < row[0] - dt / 2) {  // RK4 to the row's time
      auto add = [](std::array<double, 5> a, const std::array<double, 5>& b, double s) {
        for (int i = 0; i < 5; ++i) a[i] += s * b[i];
        return a;
      };
      auto k1 = f(t, y), k2 = f(t + dt / 2, add(y, k1, dt / 2)), k3 = f(t + dt / 2, add(y, k2, dt / 2)), k4 = f(t + dt, add(y, k3, dt));
      for (int i = 0; i < 5; ++i) y[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      t += dt;
    }
    double travel = row[r.csv.col("suspension_travel")], tyre = row[r.csv.col("tyre_deflection")];
    worst = std::max({worst, std::abs(travel - (y[1] - y[0])), std::abs(tyre - (y[4] - y[1])),
                      std::abs(row[r.csv.col("body_velocity")] - y[2]) * 0.01});
  }
  // The bump is 30 mm high; agreement to 1 micrometre.
  EXPECT_LT(worst, 1e-6);
  // and the bump really excited the car (guards against a solver stepping over it)
  double peak = 0;
  for (const auto& row : r.csv.rows) peak = std::max(peak, std::abs(row[r.csv.col("suspension_travel")]));
  EXPECT_GT(peak, 0.01);
}

// ---- pendulum through a modulated transformer -----------------------------------
// Exact period of a pendulum with inertia I about the pivot: T = 4 sqrt(I/(m g L)) K(k),
// k = sin(theta0/2), K from the arithmetic-geometric mean.
TEST(PendulumMtf, ConservesEnergyAndHasTheExactPeriod) {
  SimRun r = run(PENDULUM_SIM, "--interval 0.001", "pendulum");
  ASSERT_EQ(r.status, 0) << r.log;
  const double m = 1, L = 1, g = 9.81, J = 0.01, theta0 = 0.5;
  double E0 = r.csv.rows.front()[r.csv.col("E")];
  double worst = 0;
  for (const auto& row : r.csv.rows) worst = std::max(worst, rel_err(row[r.csv.col("E")], E0));
  EXPECT_LT(worst, 1e-7);  // rtol 1e-10 over 10 s
  double a = 1, b = std::cos(theta0 / 2);  // AGM(1, sqrt(1 - k^2))
  for (int i = 0; i < 30; ++i) {
    double an = (a + b) / 2;
    b = std::sqrt(a * b);
    a = an;
  }
  double K = M_PI / (2 * a);
  double period = 4 * std::sqrt((J + m * L * L) / (m * g * L)) * K;
  // First downward zero crossing of theta is at a quarter period: interpolate.
  std::size_t c = r.csv.col("theta");
  double crossing = NAN;
  for (std::size_t i = 1; i < r.csv.rows.size(); ++i) {
    double y0 = r.csv.rows[i - 1][c], y1 = r.csv.rows[i][c];
    if (y0 > 0 && y1 <= 0) {
      double t0 = r.csv.rows[i - 1][0], t1 = r.csv.rows[i][0];
      crossing = t0 + (t1 - t0) * y0 / (y0 - y1);
      break;
    }
  }
  // linear interpolation over a 1 ms grid near the steepest point: ~1e-7 s
  EXPECT_NEAR(crossing, period / 4, 1e-6);
}

// ---- a nonlinear implicit law solved by IDA ---------------------------------------
TEST(NonlinearDae, IdaSatisfiesTheImplicitLawAtEveryRow) {
  SimRun r = run(DAE_SIM, "--rtol 1e-9 --atol 1e-11", "nonlinear_dae");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_GT(r.csv.rows.size(), 100u);
  double worst = 0;
  for (const auto& row : r.csv.rows) {
    double t = row[0], vc = row[r.csv.col("vc")], i = row[r.csv.col("i")];
    double e = std::sin(2 * M_PI * t) - vc;  // the diode's effort from the 1-junction
    worst = std::max(worst, std::abs(e - (0.1 * i + i * i * i)));
  }
  EXPECT_LT(worst, 1e-6);
}

// ---- divergence is reported, not written as NaN rows ------------------------------
TEST(Divergence, StopsWithAReportAndKeepsTheRows) {
  SimRun r = run(BLOWUP_SIM, "", "blowup");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.log.find("cap.q"), std::string::npos) << r.log;  // names the state
  EXPECT_NE(r.log.find("t = "), std::string::npos) << r.log;   // and the time
  ASSERT_FALSE(r.csv.rows.empty());
  for (const auto& row : r.csv.rows) {
    EXPECT_LT(row[0], 1.0 + 1e-9);
    for (double v : row) EXPECT_TRUE(std::isfinite(v));
  }
}

}  // namespace
