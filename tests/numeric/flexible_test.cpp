// flexible_test.cpp — flexible beams (issue 4): the rotating beam against the
// Rayleigh-Ritz eigenproblem of thesis eq. 3.50, computed here independently
// of the compiler (own cantilever modes, own quadrature); convergence of the
// tip deflection with the number of modes; energy conservation of the
// flexible double pendulum; the flexible crank-rocker against the rigid one
// as the coupler stiffens, and its coupler buckling at the Euler load; the
// space manipulator's joint torques against a planar Newton-Euler inverse
// dynamics written here, and its tip deviation as the links stiffen.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "sim_run.hpp"

namespace {

using numeric::run;

// The beam of examples/rotating_beam (thesis Fig. 9-11).
constexpr double kLength = 8.0, kDensity = 2766.67, kYoung = 6.8952e10;
constexpr double kWidth = 3.675e-2, kHeight = 1.986e-3;  // width in the plane of rotation
constexpr double kPi = 3.14159265358979323846;

/// Cantilever mode i (0-based) and its first two derivatives at x, from the
/// classical closed form (Craig 1981; thesis eq. 9.14), unnormalised.
struct Cantilever {
  double beta, sigma;
  explicit Cantilever(int i, double length = kLength) {
    // root of cos b cosh b + 1 = 0 near (2 i + 1) pi / 2, by Newton's method
    double b = (2 * i + 1) * kPi / 2 + (i == 0 ? 0.3 : 0.0);
    for (int k = 0; k < 50; ++k) {
      const double f = std::cos(b) * std::cosh(b) + 1, df = -std::sin(b) * std::cosh(b) + std::cos(b) * std::sinh(b);
      b -= f / df;
    }
    sigma = (std::cosh(b) + std::cos(b)) / (std::sinh(b) + std::sin(b));
    beta = b / length;
  }
  double at(double x, int d) const {
    const double z = beta * x, s = std::pow(beta, d);
    switch (d) {
      case 0: return std::cosh(z) - std::cos(z) - sigma * (std::sinh(z) - std::sin(z));
      case 1: return s * (std::sinh(z) + std::sin(z) - sigma * (std::cosh(z) - std::cos(z)));
      default: return s * (std::cosh(z) + std::cos(z) - sigma * (std::sinh(z) + std::sin(z)));
    }
  }
};

/// Composite Simpson rule on [0, L] with 4000 intervals.
template <class F>
double simpson(F f, double L = kLength) {
  const int n = 4000;
  const double h = L / n;
  double s = f(0.0) + f(L);
  for (int k = 1; k < n; ++k) s += (k % 2 ? 4 : 2) * f(k * h);
  return s * h / 3;
}

/// Natural frequencies (rad/s, ascending) of eq. 3.50, [K + W^2 (Ks - M)] a = w^2 M a,
/// with n cantilever modes; without geometric stiffness Ks is left out (eq. 3.55).
/// A negative w^2 (an unstable mode) is returned as -sqrt(-w^2).
std::vector<double> rayleigh_ritz(double spin, bool geometric, int n = 3) {
  const double EI = kYoung * kHeight * std::pow(kWidth, 3) / 12, rhoA = kDensity * kWidth * kHeight;
  Eigen::MatrixXd K(n, n), Ks(n, n), M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Cantilever a(i), b(j);
      K(i, j) = EI * simpson([&](double x) { return a.at(x, 2) * b.at(x, 2); });
      Ks(i, j) = rhoA * simpson([&](double x) { return 0.5 * (kLength * kLength - x * x) * a.at(x, 1) * b.at(x, 1); });
      M(i, j) = rhoA * simpson([&](double x) { return a.at(x, 0) * b.at(x, 0); });
    }
  Eigen::MatrixXd stiffness = K - spin * spin * M;
  if (geometric) stiffness += spin * spin * Ks;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness, M);
  std::vector<double> w;
  for (int k = 0; k < n; ++k) {
    const double w2 = solver.eigenvalues()(k);
    w.push_back(w2 >= 0 ? std::sqrt(w2) : -std::sqrt(-w2));
  }
  return w;
}

struct Mode { double omega, zeta; };

/// The simulator's --linearize-at modes at t_lin, after a spin-up to `spin`
/// in spin_up_s; the rigid-body zeros (quaternion norm, frame) left out.
std::vector<Mode> linearised_modes(const char* sim, double spin, double spin_up_s, double t_lin, const std::string& tag) {
  std::ostringstream args;
  args.precision(17);
  args << "--set Omega_s=" << spin << " --set T_s=" << spin_up_s << " --t-end " << t_lin << " --linearize-at " << t_lin;
  auto r = run(sim, args.str(), tag);
  EXPECT_EQ(r.status, 0) << r.log;
  std::vector<Mode> modes;
  for (const auto& row : r.csv.rows)
    if (row[1] > 1e-3) modes.push_back({row[1], row[3]});
  return modes;
}

TEST(RotatingBeam, FrequenciesFromTheLinearisationMatchRayleighRitzAndRiseWithSpin) {
  double previous = 0;
  for (double spin : {0.0, 1.0, 2.0, 3.0, 4.0, 5.0}) {
    // a slow spin-up (10 s) leaves the beam vibrating by millimetres about its
    // steady state; after a 1 s spin-up to 4 rad/s it would swing by metres and
    // the linearisation about that state differs from eq. 3.50 by 2e-6
    const auto modes = linearised_modes(ROTATING_BEAM_SIM, spin, 10, 12, "rotating_beam_lin_" + std::to_string(int(spin)));
    const auto expected = rayleigh_ritz(spin, true);
    ASSERT_GE(modes.size(), 3u) << "spin " << spin;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(modes[k].omega, expected[k], 1e-7 * expected[k]) << "spin " << spin << " mode " << k + 1;
      EXPECT_NEAR(modes[k].zeta, 0, 1e-6) << "undamped beam, spin " << spin;
    }
    EXPECT_GT(modes[0].omega, previous) << "the first frequency rises with spin (stiffening)";
    previous = modes[0].omega;
  }
}

TEST(RotatingBeam, WithoutGeometricStiffnessTheFirstFrequencyFallsTowardsZero) {
  // eq. 3.55: w1^2 = w0^2 - W^2 with exact cantilever modes; at W = 2.8 rad/s
  // it is down to 0.79 rad/s from 2.91 (beyond w0 the mode is unstable: the
  // next test). A slow spin-up: the linear model's static deflection grows
  // as 1 / (w0^2 - W^2), and a fast one would reach the modal limit first.
  const double w0 = rayleigh_ritz(0, false)[0];
  for (double spin : {1.0, 2.0, 2.5, 2.8}) {
    const auto modes = linearised_modes(ROTATING_BEAM_LINEAR_SIM, spin, 10, 12, "rotating_beam_linear_" + std::to_string(int(10 * spin)));
    ASSERT_FALSE(modes.empty());
    const double expected = rayleigh_ritz(spin, false)[0];
    EXPECT_NEAR(expected, std::sqrt(w0 * w0 - spin * spin), 1e-9 * w0);
    EXPECT_NEAR(modes[0].omega, expected, 1e-7 * expected) << "spin " << spin;
  }
}

TEST(RotatingBeam, AtFourRadPerSecondTheLinearModelDivergesAndTheSimulatorSaysSo) {
  // thesis Fig. 9-15: Omega_s = 4 rad/s is above the first natural frequency (2.91 rad/s)
  auto linear = run(ROTATING_BEAM_LINEAR_SIM, "--set Omega_s=4", "rotating_beam_linear_diverges");
  EXPECT_EQ(linear.status, 1) << linear.log;
  EXPECT_NE(linear.log.find("state 'blade.eta.q[1]'"), std::string::npos) << linear.log;
  EXPECT_NE(linear.log.find("is beyond its limit"), std::string::npos) << linear.log;
  EXPECT_NE(linear.log.find("without geometric stiffness"), std::string::npos) << linear.log;
  ASSERT_FALSE(linear.csv.rows.empty());
  const double stopped = linear.csv.rows.back()[0];
  EXPECT_GT(stopped, 5.0);   // the spin passes 2.91 rad/s at 8 s; the deflection then grows as e^(2.7 t)
  EXPECT_LT(stopped, 15.0);
  // with geometric stiffness the same spin-up stays small (thesis: bounded, ~0.3 m)
  auto stiff = run(ROTATING_BEAM_SIM, "--set Omega_s=4", "rotating_beam_ws4");
  ASSERT_EQ(stiff.status, 0) << stiff.log;
  EXPECT_LT(stiff.csv.max_abs("tip_deflection"), 1.0);
}

TEST(RotatingBeam, InJointCoordinatesItIsAnOdeOfItsModesAndAgreesWithMultipliers) {
  // constraints = coordinates: the hub's prescribed turn is a rate source, the
  // beam a tree node whose modal accelerations the tree elimination solves;
  // the simulator integrates the three modal coordinates and their rates
  // (six states, no multipliers) and must follow the lagrange run (IDA, 31
  // unknowns) to the tolerances both are run at. Measured: 1.4e-9 m of a
  // 0.28 m deflection at rtol 1e-10 (CVODE against IDA).
  auto coords = run(ROTATING_BEAM_COORDINATES_SIM, "--solver cvode --rtol 1e-10 --atol 1e-12", "rotating_beam_coords");
  auto rows = run(ROTATING_BEAM_SIM, "--rtol 1e-10 --atol 1e-12", "rotating_beam_rows");
  ASSERT_EQ(coords.status, 0) << coords.log;
  ASSERT_EQ(rows.status, 0) << rows.log;
  EXPECT_GT(rows.csv.max_abs("tip_deflection"), 0.25);
  EXPECT_LT(max_difference(coords.csv, rows.csv, "tip_deflection"), 1e-8);
  EXPECT_LT(max_difference(coords.csv, rows.csv, "eta1"), 1e-8);
  EXPECT_LT(max_difference(coords.csv, rows.csv, "spin"), 1e-9);
  // and under RK4 at a 2 ms step (what an ODE allows): within 1e-6 m of the reference
  auto rk4 = run(ROTATING_BEAM_COORDINATES_SIM, "--solver rk4 --step 0.002", "rotating_beam_coords_rk4");
  ASSERT_EQ(rk4.status, 0) << rk4.log;
  EXPECT_LT(max_difference(rk4.csv, rows.csv, "tip_deflection"), 1e-6);
}

TEST(RotatingBeam, TipDeflectionConvergesWithTheNumberOfModes) {
  // Omega_s = 2 rad/s, T_s = 15 s: the tip deflection at t = 8 s (near its largest)
  // with 1, 2, 3 and 4 cantilever modes; each mode added changes it less.
  std::vector<double> tip;
  for (const char* sim : {ROTATING_BEAM_1_SIM, ROTATING_BEAM_2_SIM, ROTATING_BEAM_SIM, ROTATING_BEAM_4_SIM}) {
    auto r = run(sim, "--t-end 8", "rotating_beam_modes_" + std::to_string(tip.size() + 1));
    ASSERT_EQ(r.status, 0) << r.log;
    tip.push_back(r.csv.at(8.0, "tip_deflection"));
  }
  for (std::size_t k = 0; k + 2 < tip.size(); ++k)
    EXPECT_LT(std::abs(tip[k + 2] - tip[k + 1]), std::abs(tip[k + 1] - tip[k])) << "modes " << k + 1 << ".." << k + 3;
  EXPECT_LT(std::abs(tip[3] - tip[2]), 1e-3 * std::abs(tip[3])) << tip[2] << " vs " << tip[3];
}

TEST(FlexibleDoublePendulum, ConservesEnergyToTheIntegratorTolerance) {
  // undamped: kinetic + gravity + elastic energy of both beams is constant;
  // the drift must shrink with the tolerance (it is integration error).
  double drift[2];
  int k = 0;
  for (const char* rtol : {"1e-7", "1e-9"}) {
    auto r = run(FLEXIBLE_DOUBLE_PENDULUM_SIM, std::string("--t-end 2 --rtol ") + rtol, std::string("fdp_energy_") + rtol);
    ASSERT_EQ(r.status, 0) << r.log;
    drift[k++] = r.csv.max_deviation("energy");
  }
  EXPECT_LT(drift[1], 1e-7) << "J, of 0.31 J";
  EXPECT_LT(drift[1], 0.1 * drift[0]) << drift[0] << " then " << drift[1];
}

TEST(FlexibleDoublePendulumFE, ReducedBricksAndBuiltInBeamsAgreeInThePlane) {
  // examples/flexible_double_pendulum_fe, held in its plane (the knee a hinge
  // about y): strips reduced from 1200 bricks beside built-in beams, one run.
  auto r = run(FLEXIBLE_DOUBLE_PENDULUM_FE_PLANAR_SIM, "", "fdp_fe_planar");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 1001u);
  const auto c = [&](const char* name) { return r.csv.col(name); };
  double tip = 0, deflection[2] = {0, 0}, peak[2] = {0, 0};
  for (const auto& row : r.csv.rows) {
    if (row[0] > 2 + 1e-9) break;  // a double pendulum is chaotic: compare before the runs separate
    tip = std::max(tip, std::hypot(row[c("fe_tip_x")] - row[c("eb_tip_x")], row[c("fe_tip_z")] - row[c("eb_tip_z")]));
    for (int b = 0; b < 2; ++b) {
      const std::string k = std::to_string(b + 1);
      deflection[b] = std::max(deflection[b], std::abs(row[c(("fe_deflection_" + k).c_str())] - row[c(("eb_deflection_" + k).c_str())]));
      peak[b] = std::max(peak[b], std::abs(row[c(("eb_deflection_" + k).c_str())]));
    }
  }
  EXPECT_LT(tip, 5e-4) << "m over 2 s; measured 1.25e-4 m";
  EXPECT_LT(deflection[0], 0.02 * peak[0]) << "measured 0.7 % of the peak";
  EXPECT_LT(deflection[1], 0.02 * peak[1]) << "measured 1.2 % of the peak";
  EXPECT_LT(r.csv.max_deviation("fe_energy"), 1e-6) << "J of 0.31 J; measured 2.5e-7";
  EXPECT_LT(r.csv.max_deviation("eb_energy"), 1e-6) << "J; measured 2.5e-7";
  // held in the plane, neither strip bends sideways (the reduced one is nudged
  // by its modes' 1.2e-6 mixing of the two bending planes:
  // examples/flexible_double_pendulum_fe/README.md)
  EXPECT_LT(r.csv.max_abs("fe_lateral"), 1e-6) << "m; measured 2.3e-7";
  EXPECT_LT(r.csv.max_abs("eb_lateral"), 1e-7) << "m; measured 1.9e-9";
}

TEST(FlexibleDoublePendulumFE, OnABallJointTheLowerStripRollsOver) {
  // The document's scene: on the ball joint the lower strip turns about its
  // own axis, its 2 mm side into the plane of bending, and bends sideways
  // until the linear modal body's validity check stops the run.
  auto r = run(FLEXIBLE_DOUBLE_PENDULUM_FE_SIM, "", "fdp_fe_ball");
  EXPECT_NE(r.status, 0) << r.log;
  EXPECT_NE(r.log.find("beyond its limit"), std::string::npos) << r.log;
  EXPECT_GT(std::abs(r.csv.at(0.5, "roll_2")), 0.5) << "sine of the roll; measured 0.98 at 0.5 s";
  EXPECT_GT(r.csv.max_abs("lateral_2"), 0.05) << "m; measured 0.09 m";
}

TEST(FlexibleDoublePendulum, OnABallJointTheLowerStripRollsAsTheReducedOneDoes) {
  // The built-in strips start from exact symmetry, so the roll grows from
  // rounding level (about e^(30 t)) and shows after 2 s, not at once.
  auto r = run(FLEXIBLE_DOUBLE_PENDULUM_SIM, "--t-end 3", "fdp_roll");
  ASSERT_EQ(r.status, 0) << r.log;
  EXPECT_LT(std::abs(r.csv.at(1.0, "roll_2")), 1e-12) << "measured 1.1e-18";
  double late = 0;
  for (const auto& row : r.csv.rows)
    if (row[0] >= 2.5 - 1e-9) late = std::max(late, std::abs(row[r.csv.col("roll_2")]));
  EXPECT_GT(late, 0.3) << "measured 0.81 at 2.5 s";
}

// The coupler of examples/crank_rocker_flexible (thesis Fig. 9-16): aluminium,
// 10 mm deep in the mechanism plane, 15 mm wide, 0.61 m between its pins.
constexpr double kCouplerE = 6.895e10, kCouplerH = 0.010, kCouplerB = 0.015, kCouplerLength = 0.610;
/// Euler load of a pinned-pinned column, pi^2 E I / L^2 (2286 N).
double coupler_euler_load(double E = kCouplerE) {
  return kPi * kPi * E * kCouplerB * std::pow(kCouplerH, 3) / 12 / (kCouplerLength * kCouplerLength);
}

TEST(CrankRockerFlexible, ApproachesTheRigidMechanismAsTheCouplerStiffens) {
  // The coupler's quasi-static deflection, and so every difference it makes
  // to the mechanism, scales as 1/E: ten times stiffer, ten times closer to
  // examples/crank_rocker (itself checked against a closed-form 1-DOF model
  // in mechanism_test.cpp). The beam has the rigid coupler's mass and inertia.
  auto rigid = run(CRANK_ROCKER_SIM, "", "crf_rigid");
  ASSERT_EQ(rigid.status, 0) << rigid.log;
  std::vector<double> gap;
  for (double scale : {1.0, 10.0, 100.0}) {
    auto flex = run(CRANK_ROCKER_FLEXIBLE_SIM, "--set E_coupler=" + std::to_string(kCouplerE * scale),
                    "crf_stiff_" + std::to_string(int(scale)));
    ASSERT_EQ(flex.status, 0) << flex.log;
    ASSERT_EQ(flex.csv.rows.size(), rigid.csv.rows.size());
    double worst = 0;  // crank speed, rad/s, over the whole start-up
    for (std::size_t k = 0; k < rigid.csv.rows.size(); ++k)
      worst = std::max(worst, std::abs(flex.csv.rows[k][flex.csv.col("omega_crank")] - rigid.csv.rows[k][rigid.csv.col("omega_crank")]));
    gap.push_back(worst);
    // nominal: no buckling, the coupler stays well below its Euler load and bends by millimetres
    EXPECT_LT(flex.csv.max_abs("axial_force"), 0.5 * coupler_euler_load(kCouplerE * scale));
    EXPECT_LT(flex.csv.max_abs("deflection_mid"), 0.01 / scale);
  }
  EXPECT_LT(gap[0], 0.05) << "rad/s";   // measured 0.013
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(gap[k + 1], 0.2 * gap[k]) << "E x10 must bring it ~10x closer: " << gap[k] << " then " << gap[k + 1];
    EXPECT_GT(gap[k + 1], 0.05 * gap[k]) << "the gap should scale as 1/E, not vanish: " << gap[k] << " then " << gap[k + 1];
  }
}

TEST(CrankRockerFlexible, HeavyRockerBucklesTheCouplerAtItsEulerLoadAndTheRunStopsWithAReport) {
  // Thesis §9.4: with the rocker's mass and inertia x200 the compressive load
  // after the first crank turn exceeds the coupler's Euler load and the
  // coupler buckles "at about 0.4 second". The model keeps the foreshortening
  // in the joint kinematics, so the buckled column carries its Euler load
  // while mode 1 grows; the run stops where mode 1 leaves the model's range.
  auto r = run(CRANK_ROCKER_FLEXIBLE_SIM, "--set rocker_scale=200", "crf_buckles");
  EXPECT_EQ(r.status, 1) << r.log;
  EXPECT_NE(r.log.find("state 'coupler.eta.q[1]'"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("mode 1 of beam `coupler`"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("buckling load"), std::string::npos) << r.log;
  ASSERT_FALSE(r.csv.rows.empty());
  for (const auto& row : r.csv.rows)
    for (double v : row) ASSERT_TRUE(std::isfinite(v));
  const double stopped = r.csv.rows.back()[0];
  EXPECT_GT(stopped, 0.3);
  EXPECT_LT(stopped, 0.45);
  // the compression first exceeds the Euler load shortly before the stop ...
  const double P_E = coupler_euler_load();
  const std::size_t axial = r.csv.col("axial_force");
  double first_over = -1;
  for (const auto& row : r.csv.rows)
    if (-row[axial] > P_E) {
      first_over = row[0];
      break;
    }
  ASSERT_GT(first_over, 0) << "the coupler never reached its Euler load";
  EXPECT_LT(stopped - first_over, 0.05);
  // ... and the buckled coupler carries it: within 1 % at the last row (measured 0.05 %)
  EXPECT_NEAR(-r.csv.rows.back()[axial], P_E, 0.01 * P_E);
  // the same mechanism with the nominal rocker does not buckle
  auto nominal = run(CRANK_ROCKER_FLEXIBLE_SIM, "", "crf_nominal");
  ASSERT_EQ(nominal.status, 0) << nominal.log;
  EXPECT_LT(nominal.csv.max_abs("axial_force"), 0.5 * P_E);
}

/// Planar inverse dynamics of the rigid space manipulator (examples/
/// space_manipulator, Table 9-1) on the planar manoeuvre: the base held,
/// joints 2, 3, 4 each turned by theta * s(t), s the cycloidal profile of
/// eqs. 9.21-9.24. Returns the torques about z at joints 2, 3, 4 (N m), each
/// the rate of angular momentum about the joint of everything outboard of it.
std::array<double, 3> manipulator_torques(double t, double theta = kPi / 2, double T = 15) {
  const double c = T / (2 * kPi), tt = std::min(t, T);
  const double s = (tt - c * std::sin(tt / c)) / T;
  const double sd = t < T ? (1 - std::cos(tt / c)) / T : 0, sdd = t < T ? std::sin(tt / c) / (c * T) : 0;
  const double L[4] = {0.3, 4.0, 5.0, 0.5}, m[3] = {30.52, 38.16, 200}, Izz[3] = {40.73, 79.53, 0.0834};
  double phi[3], w[3], a[3];  // absolute angles of link 2, link 3, payload, and their rates
  for (int k = 0; k < 3; ++k) {
    phi[k] = (k + 1) * theta * s;
    w[k] = (k + 1) * theta * sd;
    a[k] = (k + 1) * theta * sdd;
  }
  // joint k (0..2) sits at p[k]; body k's centre of mass at p[k] + L/2 along it
  struct V { double x, y; };
  V p[3], pa[3];  // positions and accelerations of the joints
  p[0] = {L[0], 0};
  pa[0] = {0, 0};
  for (int k = 1; k < 3; ++k) {
    const double l = L[k], e[2] = {std::cos(phi[k - 1]), std::sin(phi[k - 1])};
    p[k] = {p[k - 1].x + l * e[0], p[k - 1].y + l * e[1]};
    pa[k] = {pa[k - 1].x + l * (-a[k - 1] * e[1] - w[k - 1] * w[k - 1] * e[0]),
             pa[k - 1].y + l * (a[k - 1] * e[0] - w[k - 1] * w[k - 1] * e[1])};
  }
  std::array<double, 3> tau{};
  for (int k = 0; k < 3; ++k)
    for (int j = k; j < 3; ++j) {
      const double h = L[j + 1] / 2, e[2] = {std::cos(phi[j]), std::sin(phi[j])};
      const V cj = {p[j].x + h * e[0], p[j].y + h * e[1]};
      const V acj = {pa[j].x + h * (-a[j] * e[1] - w[j] * w[j] * e[0]), pa[j].y + h * (a[j] * e[0] - w[j] * w[j] * e[1])};
      const V r = {cj.x - p[k].x, cj.y - p[k].y};
      tau[static_cast<std::size_t>(k)] += Izz[j] * a[j] + m[j] * (r.x * acj.y - r.y * acj.x);
    }
  return tau;
}

TEST(SpaceManipulator, RigidJointTorquesAreThePlanarInverseDynamicsAndFlexibleLinksDeviateAsOneOverE) {
  // The model's rigid arm gets its torques from the multipliers of the
  // prescribed joint motions; here they are recomputed by Newton-Euler.
  // The flexible arm on the same joint motion deviates at the payload tip by
  // its links' bending: ten times stiffer links, ten times less.
  std::vector<double> deviation;
  for (double scale : {1.0, 10.0}) {
    auto r = run(SPACE_MANIPULATOR_SIM, "--t-end 5 --interval 0.05 --set E_link=" + std::to_string(6.895e10 * scale),
                 "space_manipulator_" + std::to_string(int(scale)));
    ASSERT_EQ(r.status, 0) << r.log;
    EXPECT_EQ(r.log.find("not unique"), std::string::npos) << r.log;
    deviation.push_back(r.csv.max_abs("tip_deviation"));
    if (scale != 1.0) continue;
    double largest = 0;
    for (double t : {0.5, 1.0, 2.0, 3.0, 4.0, 5.0})
      for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(manipulator_torques(t)[static_cast<std::size_t>(k)]));
    ASSERT_GT(largest, 1000.0);  // N m: joint 2 needs about 1.28 kN m
    for (double t : {0.5, 1.0, 2.0, 3.0, 4.0, 5.0}) {
      const auto tau = manipulator_torques(t);
      EXPECT_NEAR(r.csv.at(t, "torque2"), tau[0], 1e-5 * largest) << "t = " << t;
      EXPECT_NEAR(r.csv.at(t, "torque3"), tau[1], 1e-5 * largest) << "t = " << t;
      EXPECT_NEAR(r.csv.at(t, "torque4"), tau[2], 1e-5 * largest) << "t = " << t;
      EXPECT_NEAR(r.csv.at(t, "torque1"), 0.0, 1e-9 * largest) << "t = " << t;  // planar: nothing about x
    }
  }
  EXPECT_GT(deviation[0], 0.05) << "m: the aluminium links bend visibly (measured 0.165 m)";
  EXPECT_LT(deviation[1], 0.2 * deviation[0]) << deviation[0] << " then " << deviation[1];
  EXPECT_GT(deviation[1], 0.05 * deviation[0]) << deviation[0] << " then " << deviation[1];
}

// The clamped tube of tests/numeric/models/cantilever.mbg.
constexpr double kTubeLength = 2.0, kTubeE = 7e10, kTubeDensity = 2700;
const double kTubeI = kPi * (std::pow(0.05, 4) - std::pow(0.04, 4)) / 64;
const double kTubeArea = kPi * (0.05 * 0.05 - 0.04 * 0.04) / 4;

TEST(BeamLoads, TipForceOnAForceElementGivesTheStaticDeflectionAsModesAreAdded) {
  // F L^3 / (3 E I) for a cantilever; an assumed-modes model approaches it
  // from below (1 mode: 97 %), here at the end of a damped 2 s run.
  const double F = 100, exact = F * std::pow(kTubeLength, 3) / (3 * kTubeE * kTubeI);
  double last_gap = 1;
  for (const char* sim : {CANTILEVER_1_SIM, CANTILEVER_3_SIM, CANTILEVER_4_SIM}) {
    auto r = run(sim, "--set F=100", std::string("cantilever_static_") + std::to_string(last_gap));
    ASSERT_EQ(r.status, 0) << r.log;
    const double tip = -r.csv.rows.back()[r.csv.col("tip")];
    const double gap = (exact - tip) / exact;
    EXPECT_GT(gap, 0) << tip << " vs " << exact;   // a Ritz model is too stiff
    EXPECT_LT(gap, last_gap) << tip << " vs " << exact;
    last_gap = gap;
  }
  EXPECT_LT(last_gap, 2e-3) << "4 modes";
}

TEST(BeamLoads, AxialTipLoadLowersTheFrequenciesAsTheRayleighRitzProblemSays) {
  // A compressive dead load P at the tip, through the tip's foreshortening,
  // adds -P G to the modal stiffness, G = int phi' phi'^T dx: the frequencies
  // solve (K - P G) a = w^2 M a (cantilever buckling: P -> pi^2 EI / (4 L^2)).
  // Without geometric stiffness the load changes nothing.
  const int n = 3;
  const double P_cr = kPi * kPi * kTubeE * kTubeI / (4 * kTubeLength * kTubeLength);
  Eigen::MatrixXd K(n, n), G(n, n), M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Cantilever a(i, kTubeLength), b(j, kTubeLength);
      K(i, j) = kTubeE * kTubeI * simpson([&](double x) { return a.at(x, 2) * b.at(x, 2); }, kTubeLength);
      G(i, j) = simpson([&](double x) { return a.at(x, 1) * b.at(x, 1); }, kTubeLength);
      M(i, j) = kTubeDensity * kTubeArea * simpson([&](double x) { return a.at(x, 0) * b.at(x, 0); }, kTubeLength);
    }
  double w0 = 0;
  for (double fraction : {0.0, 0.5, 0.9}) {
    const double P = fraction * P_cr;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K - P * G, M);
    const double expected = std::sqrt(solver.eigenvalues()(0));
    std::ostringstream args;
    args.precision(17);
    args << "--set zeta=0 --set P=" << P << " --t-end 0 --linearize-at 0";
    for (const char* sim : {CANTILEVER_3_SIM, CANTILEVER_LINEAR_SIM}) {
      auto r = run(sim, args.str(), "cantilever_axial_" + std::to_string(int(10 * fraction)));
      ASSERT_EQ(r.status, 0) << r.log;
      std::vector<double> w;
      for (const auto& row : r.csv.rows)
        if (row[1] > 1e-3) w.push_back(row[1]);
      ASSERT_FALSE(w.empty()) << r.log;
      if (sim == std::string(CANTILEVER_3_SIM)) {
        EXPECT_NEAR(w[0], expected, 1e-6 * expected) << "P = " << fraction << " P_cr";
      } else {
        if (fraction == 0.0) w0 = w[0];
        EXPECT_NEAR(w[0], w0, 1e-9 * w0) << "without geometric stiffness, P = " << fraction << " P_cr";
      }
    }
    if (fraction == 0.9) EXPECT_LT(expected, 0.4 * w0);  // sqrt(1 - 0.9) would be 0.32
  }
}

TEST(MeanAxes, AFreeRodStruckAtItsEndVibratesAsItsFreeFreeModesSay) {
  // In mean axes (frame = buckens) free-free modes do not couple to the
  // rigid motion, so an end impulse J sets each mode going on its own:
  // u(L, t) = sum_k J phi_k(L)^2 / (M_k w_k) sin(w_k (t - tau/2)), whatever the
  // rod's translation and rotation do. Modes and frequencies computed here.
  const double E = 2.1e11, rho = 7850, d = 0.01, L = 1, J = 1e-4, tau = 1e-5;
  const double A = kPi * d * d / 4, I = kPi * std::pow(d, 4) / 64;
  struct FreeMode { double tip, mass, omega; };
  std::vector<FreeMode> modes;
  for (double guess : {4.73, 7.85, 11.0}) {
    double b = guess;  // root of cos b cosh b = 1
    for (int k = 0; k < 50; ++k)
      b -= (std::cos(b) * std::cosh(b) - 1) / (-std::sin(b) * std::cosh(b) + std::cos(b) * std::sinh(b));
    const double sigma = (std::cosh(b) - std::cos(b)) / (std::sinh(b) - std::sin(b));
    auto phi = [&](double x) {
      const double z = b * x / L;
      return std::cosh(z) + std::cos(z) - sigma * (std::sinh(z) + std::sin(z));
    };
    modes.push_back({phi(L), rho * A * simpson([&](double x) { return phi(x) * phi(x); }, L),
                     b * b / (L * L) * std::sqrt(E * I / (rho * A))});
  }
  EXPECT_NEAR(modes[0].omega, 289.297, 1e-3);  // rad/s
  auto r = run(FREE_BEAM_SIM, "", "free_beam");
  ASSERT_EQ(r.status, 0) << r.log;
  double worst = 0, peak = 0;
  for (const auto& row : r.csv.rows) {
    const double t = row[0];
    if (t < 2 * tau) continue;
    double u = 0;
    for (const auto& m : modes) u += J * m.tip * m.tip / (m.mass * m.omega) * std::sin(m.omega * (t - tau / 2));
    worst = std::max(worst, std::abs(row[r.csv.col("end_y")] - u));
    peak = std::max(peak, std::abs(u));
  }
  EXPECT_GT(peak, 1e-6);
  EXPECT_LT(worst, 1e-4 * peak) << "measured 2.2e-6 of the peak (the pulse's finite length)";
}

}  // namespace

namespace {

TEST(CraigBamptonBody, AReducedFEBarMovesLikeTheBuiltInBeam) {
  // The bar of ModalFile.* from 200 frame elements, reduced by mbgc-reduce to
  // its 5 lowest modes (its inertia invariants partly from lumped nodal
  // masses), beside the built-in beam with the same 2 + 3 modes, in one run.
  auto r = run(REDUCED_BLADE_SIM, "", "reduced_blade");
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 401u);
  for (const char* axis : {"[2]", "[3]"}) {
    const std::string builtin = std::string("builtin_tip") + axis, reduced = std::string("reduced_tip") + axis;
    const double peak = r.csv.max_abs(builtin);
    EXPECT_GT(peak, 1e-3) << builtin << ": the load case must bend the bar in this plane";
    double worst = 0;
    for (const auto& row : r.csv.rows) worst = std::max(worst, std::abs(row[r.csv.col(builtin)] - row[r.csv.col(reduced)]));
    EXPECT_LT(worst, 1e-5 * peak) << axis << " (peak " << peak << " m); measured 2.5e-7 (y) and 2.2e-6 (z) of the peak";
  }
  double worst = 0;
  for (const char* axis : {"[1]", "[2]", "[3]"})
    for (const auto& row : r.csv.rows)
      worst = std::max(worst, std::abs(row[r.csv.col(std::string("builtin_world") + axis)] -
                                       row[r.csv.col(std::string("reduced_world") + axis)]));
  EXPECT_LT(worst, 1e-6) << "m, of a 2 m bar; measured 4.1e-8 m";
}

TEST(ModalFile, ABeamReadFromAnFEFileMovesLikeTheBuiltInBeam) {
  // The same 2 m bar twice: once the compiler's built-in beam (3 + 2
  // cantilever modes, integrals by the compiler), once a modal-data file that
  // make_fe_beam wrote from 40 Hermite finite elements (its own modes and
  // invariants). Spun up about z under oblique gravity, it bends in both
  // planes; the two bodies must move alike, to what 40 elements resolve.
  auto builtin = run(MODAL_BEAM_SIM, "", "modal_beam");
  auto file = run(MODAL_FILE_BEAM_SIM, "", "modal_file_beam");
  ASSERT_EQ(builtin.status, 0) << builtin.log;
  ASSERT_EQ(file.status, 0) << file.log;
  ASSERT_EQ(builtin.csv.rows.size(), file.csv.rows.size());
  ASSERT_EQ(builtin.csv.rows.size(), 401u);
  for (const char* out : {"tip_y", "tip_z"}) {
    const double peak = builtin.csv.max_abs(out);
    EXPECT_GT(peak, 1e-3) << out << ": the load case must bend the bar in this plane";
    const double worst = max_difference(file.csv, builtin.csv, out);
    EXPECT_LT(worst, 1e-5 * peak) << out << " (peak " << peak << " m); measured 1.3e-7 of the peak";
  }
  // the tip in world axes: the frame's motion and the modes together
  double worst = 0;
  for (const char* out : {"tip_world[1]", "tip_world[2]", "tip_world[3]"}) worst = std::max(worst, max_difference(file.csv, builtin.csv, out));
  EXPECT_LT(worst, 1e-7) << "m, of a 2 m bar; measured 2.4e-9 m";
}

}  // namespace

namespace {

// Stretch and twist of a steel tube and rod (tests/numeric/models/rod.mbg,
// spinning_rod.mbg): fixed-free rod modes sqrt(2) sin(k_i x), k_i = (2i - 1) pi / (2L).
constexpr double kRodL = 1.5, kRodRho = 7800, kRodE = 2.1e11, kRodG = 8.1e10;
double rod_k(int i) { return (2 * i - 1) * kPi / (2 * kRodL); }
TEST(StretchAndTwist, TipForceAndTorqueGiveTheRitzSeriesThatApproachesFLOverEA) {
  const double F = 1000, T = 100, A = kPi * (0.04 * 0.04 - 0.03 * 0.03) / 4;
  const double J = kPi * (std::pow(0.04, 4) - std::pow(0.03, 4)) / 32;  // a tube's torsion constant: its polar moment
  double previous = 0;
  for (auto [sim, n] : {std::pair{ROD_1_SIM, 1}, std::pair{ROD_3_SIM, 3}}) {
    auto r = run(sim, "--set F=1000 --set T=100", "rod_" + std::to_string(n));
    ASSERT_EQ(r.status, 0) << r.log;
    double series = 0;
    for (int i = 1; i <= n; ++i) series += 8 / (kPi * kPi * (2 * i - 1) * (2 * i - 1));
    const double stretch = r.csv.rows.back()[r.csv.col("stretch")], twist = r.csv.rows.back()[r.csv.col("twist")];
    EXPECT_NEAR(stretch, F * kRodL / (kRodE * A) * series, 1e-9 * stretch) << n << " modes";
    EXPECT_NEAR(twist, T * kRodL / (kRodG * J) * series, 1e-9 * twist) << n << " modes";
    EXPECT_GT(stretch, previous) << "more modes, closer to F L / (E A) from below";
    EXPECT_LT(stretch, F * kRodL / (kRodE * A));
    previous = stretch;
  }
}

TEST(StretchAndTwist, NaturalFrequenciesOfStretchAndTwistAreTheRodsClosedForm) {
  auto r = run(ROD_3_SIM, "--set zeta=0 --t-end 0.001 --linearize-at 0.001", "rod_3_lin");
  ASSERT_EQ(r.status, 0) << r.log;
  std::vector<double> expected, got;
  for (int i = 1; i <= 3; ++i) {
    expected.push_back(rod_k(i) * std::sqrt(kRodE / kRodRho));  // axial
    expected.push_back(rod_k(i) * std::sqrt(kRodG / kRodRho));  // torsion of a tube: sqrt(G J / (rho Ip)), J = Ip
  }
  std::sort(expected.begin(), expected.end());
  for (const auto& row : r.csv.rows)
    if (row[1] > 1) got.push_back(row[1]);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t k = 0; k < got.size(); ++k) EXPECT_NEAR(got[k], expected[k], 1e-9 * expected[k]) << "mode " << k + 1;
}

TEST(StretchAndTwist, SpinStretchesARodAndAngularAccelerationTwistsATubeAsRitzAndTheClosedFormsSay) {
  // A rod spinning at Omega about z through its end: E A u'' + mu Omega^2 (x + u) = 0, u(0) = 0,
  // u'(L) = 0, so u(L) = tan(kappa L) / kappa - L with kappa = Omega sqrt(rho / E). A tube spun
  // up about its axis at alpha carries the distributed torque -rho Ip alpha: theta(L) =
  // -rho alpha L^2 / (2 G) (J = Ip). The Ritz solutions with three modes, computed here, are what
  // the model must give; they are within 0.1 % and 0.3 % of the closed forms.
  const double Omega = 300, alpha = 1e4;
  auto r = run(SPINNING_ROD_SIM, "", "spinning_rod");
  ASSERT_EQ(r.status, 0) << r.log;
  double stretch_ritz = 0, twist_ritz = 0;
  for (int i = 1; i <= 3; ++i) {
    const double k = rod_k(i), tip = std::sqrt(2.0) * std::sin(k * kRodL);
    // per unit mu (stretch) or rho Ip (twist): modal mass L, stiffness (E/rho) k^2 L, load int x chi, int chi
    const double int_x_chi = std::sqrt(2.0) * (std::sin(k * kRodL) - k * kRodL * std::cos(k * kRodL)) / (k * k);
    const double int_chi = std::sqrt(2.0) * (1 - std::cos(k * kRodL)) / k;
    stretch_ritz += tip * Omega * Omega * int_x_chi / (kRodE / kRodRho * k * k * kRodL - Omega * Omega * kRodL);
    twist_ritz += tip * -alpha * int_chi / (kRodG / kRodRho * k * k * kRodL);
  }
  const double kappa = Omega * std::sqrt(kRodRho / kRodE);
  const double stretch_exact = std::tan(kappa * kRodL) / kappa - kRodL, twist_exact = -kRodRho * alpha * kRodL * kRodL / (2 * kRodG);
  const double stretch = r.csv.rows.back()[r.csv.col("stretch")], twist = r.csv.rows.back()[r.csv.col("twist")];
  EXPECT_NEAR(stretch, stretch_ritz, 1e-6 * stretch_ritz) << "measured 1e-14";
  EXPECT_NEAR(twist, twist_ritz, 1e-6 * std::abs(twist_ritz)) << "measured 1e-12";
  EXPECT_NEAR(stretch_ritz, stretch_exact, 1e-3 * stretch_exact);
  EXPECT_NEAR(twist_ritz, twist_exact, 3e-3 * std::abs(twist_exact));
  // Tighter tolerances give a run at least as accurate, never a failed one:
  // at rtol 1e-10, atol 1e-14 IDA's Newton iteration chased rounding noise
  // and stopped at t = 0.077 s; the runtime restarts with the absolute
  // tolerances floored at what the equations resolve (error_weights.hpp).
  double error[2];
  const char* atols[2] = {"1e-10", "1e-14"};
  for (int k = 0; k < 2; ++k) {
    auto t = run(SPINNING_ROD_SIM, std::string("--rtol 1e-10 --atol ") + atols[k], std::string("spinning_rod_atol") + atols[k]);
    ASSERT_EQ(t.status, 0) << t.log;
    ASSERT_NEAR(t.csv.rows.back()[0], 0.2, 1e-12) << t.log;
    error[k] = std::max(std::abs(t.csv.rows.back()[t.csv.col("stretch")] - stretch_ritz) / stretch_ritz,
                        std::abs(t.csv.rows.back()[t.csv.col("twist")] - twist_ritz) / std::abs(twist_ritz));
  }
  std::printf("relative error against Ritz at rtol 1e-10: atol 1e-10 %.3g, atol 1e-14 %.3g\n", error[0], error[1]);
  EXPECT_LE(error[1], std::max(error[0], 1e-13));  // (both at rounding: 1e-13 of the value)
}

}  // namespace

namespace {

TEST(CentreFrame, AFreeRodStruckAtItsEndMovesAsInMeanAxes) {
  // The struck rod of MeanAxes.* twice: in its mean axes, and with its frame
  // fixed to the section at its mass centre, where each free-free mode is
  // measured from that section. Modes and rigid motions span the same space,
  // so the rod's ends must move alike in the world. They differ by what one
  // formulation holds and the other does not: the sections' rotary inertia is
  // in the frame's J0 but not in the Euler-Bernoulli modes, which in the
  // centre frame carry part of the rotation (measured: 4e-4 of the motion at
  // d = 10 mm, 1.6e-5 at 3 mm), and terms of second order in the deflection
  // (4.5e-5 at 1 mm, where the end moves by 3 mm). At 3 mm both are small.
  auto mean_axes = run(FREE_BEAM_SIM, "--set d=0.003", "free_beam_d3");
  auto centre = run(FREE_BEAM_CENTRE_SIM, "--set d=0.003", "free_beam_centre_d3");
  ASSERT_EQ(mean_axes.status, 0) << mean_axes.log;
  ASSERT_EQ(centre.status, 0) << centre.log;
  ASSERT_EQ(mean_axes.csv.rows.size(), centre.csv.rows.size());
  const double peak = mean_axes.csv.max_abs("end_world[2]");
  EXPECT_GT(peak, 1e-4) << "the strike must move the rod";
  for (const char* out : {"end_world[1]", "end_world[2]", "start_world[1]", "start_world[2]"}) {
    const double worst = max_difference(centre.csv, mean_axes.csv, out);
    EXPECT_LT(worst, 1e-4 * peak) << out << " (the end moves by " << peak << " m); measured 1.6e-5 of it";
  }
}

}  // namespace

namespace {

// Tisserand's frame (frame = tisserand, thesis §5.2.4) of the free steel rod
// of MeanAxes.* (tests/numeric/models/free_beam_tisserand.mbg): the mean axes
// with the origin at the mass centre and the foreshortening measured from its
// mean, so that the deformation carries no momentum relative to the frame.
constexpr double kRodLength = 1, kSteelRho = 7850, kSteelE = 2.1e11;

/// Free-free mode i (0-based) of a uniform beam of length L, unnormalised, and its derivatives.
struct FreeFree {
  double beta, sigma;
  explicit FreeFree(int i, double length = kRodLength) {
    double b = (2 * i + 3) * kPi / 2;  // root of cos b cosh b = 1
    for (int k = 0; k < 50; ++k) b -= (std::cos(b) * std::cosh(b) - 1) / (-std::sin(b) * std::cosh(b) + std::cos(b) * std::sinh(b));
    sigma = (std::cosh(b) - std::cos(b)) / (std::sinh(b) - std::sin(b));
    beta = b / length;
  }
  double at(double x, int d) const {
    const double z = beta * x, s = std::pow(beta, d);
    switch (d) {
      case 0: return std::cosh(z) + std::cos(z) - sigma * (std::sinh(z) + std::sin(z));
      case 1: return s * (std::sinh(z) - std::sin(z) - sigma * (std::cosh(z) + std::cos(z)));
      default: return s * (std::cosh(z) - std::cos(z) - sigma * (std::sinh(z) - std::sin(z)));
    }
  }
};

TEST(TisserandFrame, AStruckRodMovesAsInBuckensMeanAxes) {
  // Both frames are the mean axes of the same modes; they differ in where the
  // origin sits and how the foreshortening is measured, i.e. by a rigid
  // translation of second order in the deflection. The rod's ends must move alike.
  for (double spin : {0.0, 50.0}) {
    const std::string args = "--set d=0.003 --set spin=" + std::to_string(spin);
    auto buckens = run(FREE_BEAM_SIM, args, "free_beam_spin_" + std::to_string(int(spin)));
    auto tisserand = run(FREE_BEAM_TISSERAND_SIM, args, "free_beam_tisserand_spin_" + std::to_string(int(spin)));
    ASSERT_EQ(buckens.status, 0) << buckens.log;
    ASSERT_EQ(tisserand.status, 0) << tisserand.log;
    ASSERT_EQ(buckens.csv.rows.size(), tisserand.csv.rows.size());
    const double deflection = buckens.csv.max_abs("end_y");
    EXPECT_GT(deflection, 1e-5) << "the strike must bend the rod";
    EXPECT_LT(max_difference(tisserand.csv, buckens.csv, "end_y"), 1e-5 * deflection) << "spin " << spin;
    for (const char* out : {"end_world[1]", "end_world[2]", "start_world[1]", "start_world[2]"}) {
      const double worst = max_difference(tisserand.csv, buckens.csv, out);
      EXPECT_LT(worst, 1e-5 * deflection) << out << ", spin " << spin << " rad/s; measured 2.9e-6 of it";
    }
  }
}

TEST(TisserandFrame, ItsOriginIsTheMassCentreSoItMovesWithTheImpulseOverTheMass) {
  // Spinning at 50 rad/s and struck sideways, the rod vibrates, its
  // foreshortening pulses, and the spin stiffens it; its mass centre moves
  // at J / m all the same. In Tisserand's frame that is the frame's origin:
  // the model's linear momentum is m V, exactly, so V must stay J / m (world y)
  // after the pulse, and the energy must stay what the strike put in.
  const double J = 1e-4, tau = 1e-5, d = 0.003, mass = kSteelRho * kPi * d * d / 4 * kRodLength;
  auto r = run(FREE_BEAM_TISSERAND_SIM, "--set d=0.003 --set spin=50", "free_beam_tisserand_momentum");
  ASSERT_EQ(r.status, 0) << r.log;
  EXPECT_GT(r.csv.max_abs("end_y"), 1e-5);
  double worst_v = 0, e_min = 1e300, e_max = -1e300;
  for (const auto& row : r.csv.rows) {
    if (row[0] < 2 * tau) continue;
    worst_v = std::max({worst_v, std::abs(row[r.csv.col("frame_velocity[1]")]), std::abs(row[r.csv.col("frame_velocity[2]")] - J / mass),
                        std::abs(row[r.csv.col("frame_velocity[3]")])});
    e_min = std::min(e_min, row[r.csv.col("energy")]);
    e_max = std::max(e_max, row[r.csv.col("energy")]);
  }
  // measured 1.5e-9 of it; a mass centre off the origin by the foreshortening's
  // mean (about 1e-9 m here) would move it by 3e-5 of it at this spin
  EXPECT_LT(worst_v, 1e-8 * J / mass) << "m/s, of " << J / mass;
  EXPECT_LT(e_max - e_min, 1e-8 * e_max) << "J";
}

TEST(TisserandFrame, ASpinningFreeRodsFrequenciesAreTheRitzEigenproblemAboutItsCentre) {
  // A free rod spinning at W about body z (its mass centre) bends in the plane
  // of the spin with [K + W^2 (Ks - M)] a = w^2 M a, Ks from the centrifugal
  // axial force mu W^2 ((L/2)^2 - s^2) / 2 (thesis eq. 3.50 about the centre),
  // computed here with the test's own modes and quadrature.
  const double d = 0.01, spin = 150, A = kPi * d * d / 4, I = kPi * std::pow(d, 4) / 64, mu = kSteelRho * A;
  const int n = 3;
  Eigen::MatrixXd K(n, n), Ks(n, n), M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const FreeFree a(i), b(j);
      const double c = kRodLength / 2;
      K(i, j) = kSteelE * I * simpson([&](double x) { return a.at(x, 2) * b.at(x, 2); }, kRodLength);
      Ks(i, j) = mu * simpson([&](double x) { return 0.5 * (c * c - (x - c) * (x - c)) * a.at(x, 1) * b.at(x, 1); }, kRodLength);
      M(i, j) = mu * simpson([&](double x) { return a.at(x, 0) * b.at(x, 0); }, kRodLength);
    }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> spinning(K + spin * spin * (Ks - M), M), still(K, M);
  auto r = run(FREE_BEAM_TISSERAND_SIM, "--set J=0 --set spin=150 --t-end 0.001 --linearize-at 0.001", "free_beam_tisserand_lin");
  ASSERT_EQ(r.status, 0) << r.log;
  for (int k = 0; k < n; ++k) {
    const double expected = std::sqrt(spinning.eigenvalues()(k));
    double nearest = 0;
    for (const auto& row : r.csv.rows)
      if (std::abs(row[1] - expected) < std::abs(nearest - expected)) nearest = row[1];
    EXPECT_NEAR(nearest, expected, 1e-6 * expected) << "mode " << k + 1 << "\n" << r.log;
    EXPECT_GT(std::abs(expected - std::sqrt(still.eigenvalues()(k))), 1e-3 * expected) << "the spin must move mode " << k + 1;
  }
}

}  // namespace

// ---- flexible bodies as tree nodes in joint coordinates (issue 15, item 2) ----------------

struct CoordinatesCase {
  const char* name;
  const char* coordinates_sim;
  const char* rows_sim;
  const char* options;  // loads, both runs
  std::vector<const char*> outputs;
  double tolerance;  // absolute, in the outputs' units
};

constexpr const char* kTight = "--rtol 1e-10 --atol 1e-12";

class FlexibleInCoordinates : public ::testing::TestWithParam<CoordinatesCase> {};

TEST_P(FlexibleInCoordinates, TheOdeAgreesWithTheMultiplierRun) {
  // The same model with its tree joints as constraint rows (IDA, multipliers)
  // and in joint coordinates (CVODE: the beams' modal accelerations solved in
  // the tree elimination), both at the case's tolerance. Measured
  // differences at rtol 1e-10: modal file beam 5e-11 m of 0.019 m;
  // cantilever 1.9e-11 m of 0.016 m; rod stretch 1.8e-15 m, twist 3.3e-12
  // rad of 0.013 rad; spinning rod 1.1e-11 rad of 0.0015 rad; flexible double
  // pendulum (2 s) 3.9e-8 m of 0.014 m; flex_chain (1e-11) 1.2e-8 m of a
  // 2 m reach and 4.2e-10 m of 0.0042 m of deflection; at rtol 1e-9 the
  // space manipulator (6 s) 2.5e-12 m of 0.165 m; the flexible crank-rocker
  // (a cut joint) 1.7e-8 rad/s of 21.7, 2.9e-10 m of 5.0e-3 m, the cut
  // joint's axial force 1.6e-5 N of 319 N.
  const CoordinatesCase& c = GetParam();
  const std::string opts = c.options;
  auto coords = run(c.coordinates_sim, "--solver cvode " + opts, std::string(c.name) + "_coordinates");
  auto rows = run(c.rows_sim, "--solver ida " + opts, std::string(c.name) + "_rows");
  ASSERT_EQ(coords.status, 0) << coords.log;
  ASSERT_EQ(rows.status, 0) << rows.log;
  for (const char* out : c.outputs) {
    EXPECT_GT(rows.csv.max_abs(out), 100 * c.tolerance) << out << ": the case must move";
    EXPECT_LT(max_difference(coords.csv, rows.csv, out), c.tolerance) << out;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Bodies, FlexibleInCoordinates,
    ::testing::Values(
        CoordinatesCase{"modal_file_beam", MODAL_FILE_BEAM_COORDINATES_SIM, MODAL_FILE_BEAM_SIM, kTight, {"tip_y", "tip_z"}, 1e-9},
        CoordinatesCase{"cantilever", CANTILEVER_3_COORDINATES_SIM, CANTILEVER_3_SIM, "--set F=50 --set P=100 --rtol 1e-10 --atol 1e-12", {"tip"}, 1e-9},
        CoordinatesCase{"rod", ROD_3_COORDINATES_SIM, ROD_3_SIM, "--set F=1000 --set T=100 --rtol 1e-10 --atol 1e-12", {"twist"}, 1e-10},
        CoordinatesCase{"spinning_rod", SPINNING_ROD_COORDINATES_SIM, SPINNING_ROD_SIM, kTight, {"stretch", "twist"}, 1e-10},
        CoordinatesCase{"flex_chain", FLEX_CHAIN_COORDINATES_SIM, FLEX_CHAIN_SIM, "--rtol 1e-11 --atol 1e-13", {"mid1", "mid2", "tipx", "tipy"}, 5e-8},
        CoordinatesCase{"flexible_double_pendulum", FLEXIBLE_DOUBLE_PENDULUM_COORDINATES_SIM, FLEXIBLE_DOUBLE_PENDULUM_SIM,
                        "--t-end 2 --rtol 1e-10 --atol 1e-12", {"deflection_1", "deflection_2", "tip_x", "tip_z"}, 2e-7},
        CoordinatesCase{"space_manipulator", SPACE_MANIPULATOR_COORDINATES_SIM, SPACE_MANIPULATOR_SIM, "--t-end 6 --rtol 1e-9 --atol 1e-11",
                        {"tip_deviation", "link2_mid", "link3_mid"}, 1e-10},
        // reduced FE arms (mbgc-reduce) on every joint kind, to ground, to each other and to rigid
        // bodies (issue 17, point 2); measured at rtol 1e-11: 3.5e-8 m and 3.7e-8 m of bending
        CoordinatesCase{"reduced_joints", REDUCED_JOINTS_COORDINATES_SIM, REDUCED_JOINTS_SIM, "--rtol 1e-11 --atol 1e-13",
                        {"tip2[3]", "tip3[1]", "tip4[3]", "bend1", "bend3[3]", "bend4[3]", "bob_position[1]"}, 1e-7},
        // and closed by a connection rod, the cut joint in coordinates; measured 2.3e-9 m, 1.7e-9 m of bending
        CoordinatesCase{"reduced_loop", REDUCED_LOOP_COORDINATES_SIM, REDUCED_LOOP_SIM, "--rtol 1e-9 --atol 1e-11",
                        {"tip2[1]", "tip2[3]", "bend1", "bend2[3]"}, 2e-8},
        // a loop: j3 is a cut joint on the coupler's pinned end (multipliers at acceleration level)
        CoordinatesCase{"crank_rocker_flexible", CRANK_ROCKER_FLEXIBLE_COORDINATES_SIM, CRANK_ROCKER_FLEXIBLE_SIM,
                        kTight, {"omega_rocker", "deflection_mid", "eta1"}, 2e-7}),
    [](const ::testing::TestParamInfo<CoordinatesCase>& i) { return std::string(i.param.name); });

TEST(FlexChain, InJointCoordinatesTheEnergyIsConstantToTheTolerance) {
  // Undamped, joints on sections that turn with the modes: a kinematic slip
  // (a wrong angular velocity of a turned seat, say) would feed or drain
  // energy at a rate no tolerance removes. Measured drift over 3 s: 1.9e-7 J
  // at rtol 1e-8, 4.8e-9 J at 1e-10 (of 8.7 J).
  double drift[2];
  int k = 0;
  for (const char* rtol : {"1e-8", "1e-10"}) {
    auto r = run(FLEX_CHAIN_COORDINATES_SIM, std::string("--solver cvode --atol 1e-14 --rtol ") + rtol, std::string("flex_chain_energy_") + rtol);
    ASSERT_EQ(r.status, 0) << r.log;
    drift[k++] = r.csv.max_deviation("energy");
  }
  EXPECT_LT(drift[1], 1e-7);
  EXPECT_LT(drift[1], 0.1 * drift[0]) << drift[0] << " then " << drift[1];
}
