// crank_rocker_flexible_by_hand — the flexible crank-rocker of
// examples/crank_rocker_flexible (thesis §9.4) written by hand as planar
// multibody equations, against the simulator mbgc generates from the model.
//
// The mechanism: crank (angle th1 about O2, with the motor's rotor), coupler
// (a beam whose floating frame sits on the section at joint A, x along the
// chord A -> B, with two pinned-pinned in-plane bending modes eta), rocker
// (angle th4 about O4), and the separately excited DC motor on the crank.
// The coordinates are the tree's joint angles and the modes,
//   q = (th1, th2, eta1, eta2, th4),
// th2 the angle of the coupler's section at A against the crank. That
// section turns with the beam's slope s = phi'(0) eta, by psi = 2 atan(s/2),
// so the frame's angle is phi = th1 + th2 - psi. The loop is closed at B by
// two multipliers holding the world position of the rocker's B on the
// coupler's B,
//   g(q) = O4 + a3 (cos th4, sin th4) - A - l(eta) (cos phi, sin phi),
//   l(eta) = L - eta^T a(L) eta / 2   (the foreshortening of the chord),
// at acceleration level with Baumgarte's g'' + 2 w g' + w^2 g = 0 (w = 20
// rad/s, what mbgc's joint-coordinate form puts on a cut joint): an ODE of
// 11 states, integrated by classic RK4. B does not move across the chord
// (pinned-pinned: phi(L) = 0) and the turn of its section does not enter a
// planar pin; the revolute joint's other three rows (out of the plane, and
// the axes' alignment) vanish identically in the plane, and mbgc drops them
// too (its multiplier system is 2 x 2).
//
// The coupler in its frame (body axes, v = (V, omega, eta')): kinetic energy
// T = v^T M(eta) v / 2 with, per unit of the modal integrals the compiler
// computes (compiler/flex/beam_modes, times mu = rho A),
//   first moment      s = (m L/2 - eta^T load eta / 2, mean . eta)
//   omega-omega       J0 + eta^T (mass - spin) eta
//   V_x-eta'          -load eta        (the foreshortening moves mass along x)
//   V_y-eta'          mean,   omega-eta'   moment,   eta'-eta'   mass
// and the Boltzmann-Hamel equations
//   d/dt(M v) + (gyroscopic: omega x p_V, V x p_V) - dT/deta + K eta + D eta' = F,
// projected onto q by the velocity map v = J(q) q' (Kane); the geometric
// stiffness is the chord's foreshortening in g and in M (load, spin). The
// motor: L_a i' = V - R_a i - K_m th1', torque K_m i - D th1'.
//
// Per evaluation: three sin/cos pairs, the 4 x 4 mass matrix of crank and
// coupler written from the sparse J (no 5 x 5 products), one L D L^T of it
// with three right-hand sides (the forces and the cut joint's two
// directions), and the 2 x 2 Schur complement for the multipliers (the
// rocker adds its 1 / I3). These are the states and the ODE of mbgc's
// joint-coordinate form, so under the same RK4 step the two must give the
// same numbers up to rounding.
//
// Printed: the outputs at t = 1 s from both (they must agree: the same
// equations), at a small step and at one common step, each one's error in
// omega_crank against its own small-step reference, and the wall time each
// needs for omega_crank within 1e-6 rad/s of that reference: the
// hand-written model timed in process (the fastest of repeated runs), the
// generated simulator by its own run summary (the fastest of ten runs).
//   crank_rocker_flexible_by_hand PATH/TO/bench_crank_rocker_flexible
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_crank_rocker_flexible_model.hpp"
#include "by_hand.hpp"
#include "flex/beam_modes.hpp"
#include "rk4.hpp"

namespace {

// examples/crank_rocker_flexible/crank_rocker_flexible.mbg and examples/dc_motor/motor.mbg
constexpr double a1 = 0.102, a2 = 0.610, a3 = 0.406, a4 = 0.559;
constexpr double I1 = 0.00707 + 0.565, I2 = 0.01245, I3 = 0.042152;
constexpr double h_sec = 0.010, b_sec = 0.015, E_coupler = 6.895e10, modal_damping = 0.01;
constexpr double V_supply = 60, R_a = 0.4, L_a = 0.05, K_m = 0.678, D_shaft = 0.226;
constexpr double kStabilisation = 20;  // rad/s: mbgc's default for a cut joint in joint coordinates
constexpr double kTEnd_s = 1;
constexpr double kTarget = 1e-6;  // rad/s on omega_crank at kTEnd_s

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
// th1, th2, eta1, eta2, th4 | their rates | armature current
using State = Eigen::Matrix<double, 11, 1>;

struct Outputs {
  double omega_crank, omega_rocker, current, deflection_mid, eta1, eta2;
};

/// A X = B for symmetric positive definite A (its lower triangle read), B
/// overwritten by X: L D L^T (no square roots; one division per pivot),
/// unrolled by the compiler at these fixed sizes (Eigen's LLT::solveInPlace
/// takes its general blocked path for a 4 x 3 right-hand side).
template <int N, int K>
inline void ldlt_solve(Eigen::Matrix<double, N, N>& A, Eigen::Matrix<double, N, K>& B) {
  double inv[N];  // 1 / D(j)
  for (int j = 0; j < N; ++j) {
    double d = A(j, j);
    for (int k = 0; k < j; ++k) d -= A(j, k) * A(j, k) * A(k, k);
    A(j, j) = d;
    inv[j] = 1 / d;
    for (int i = j + 1; i < N; ++i) {
      double v = A(i, j);
      for (int k = 0; k < j; ++k) v -= A(i, k) * A(j, k) * A(k, k);
      A(i, j) = v * inv[j];
    }
  }
  for (int c = 0; c < K; ++c) {
    for (int i = 0; i < N; ++i) {  // L z = b
      double v = B(i, c);
      for (int k = 0; k < i; ++k) v -= A(i, k) * B(k, c);
      B(i, c) = v;
    }
    for (int i = N - 1; i >= 0; --i) {  // D L^T x = z
      double v = B(i, c) * inv[i];
      for (int k = i + 1; k < N; ++k) v -= A(k, i) * B(k, c);
      B(i, c) = v;
    }
  }
}

struct ByHand {
  // coupler: mass, J0 about A, modal integrals times mu, stiffness, damping
  double m = 0, J0 = 0, L = a2;
  Vec2 mean, moment, slope_A, shape_mid;
  Mat2 mass, load, spin, mass_minus_spin, aL, K, D;
  double theta1_0 = 0, theta2_0 = 0, theta3_0 = 0;

  ByHand() {
    const mbgc::flex::BeamModes shapes(mbgc::flex::Supports::PinnedPinned, a2, 2);
    const mbgc::flex::ModalIntegrals in = mbgc::flex::modal_integrals(shapes);
    const mbgc::flex::Matrix shortening = mbgc::flex::axial_up_to(shapes, a2);  // a(L)
    const double m2 = 12 * I2 / (a2 * a2), density = m2 / (a2 * h_sec * b_sec), area = h_sec * b_sec;
    const double Iz = b_sec * h_sec * h_sec * h_sec / 12, mu = density * area, EI = E_coupler * Iz;
    m = a2 * mu;
    J0 = mu * a2 * a2 * a2 / 3 + density * a2 * Iz;  // the line about A plus the sections' own inertia
    for (int i = 0; i < 2; ++i) {
      const auto I = static_cast<std::size_t>(i);
      mean(i) = mu * in.mean[I];
      moment(i) = mu * in.moment[I];
      slope_A(i) = shapes.shape(i, 0, 1);
      // (mode 2's node at the middle: its rounding is the zero it is, as in mbgc)
      shape_mid(i) = std::abs(shapes.shape(i, a2 / 2)) <= 1e-12 ? 0.0 : shapes.shape(i, a2 / 2);
      for (int j = 0; j < 2; ++j) {
        const auto J = static_cast<std::size_t>(j);
        mass(i, j) = mu * in.mass[I][J];
        load(i, j) = mu * in.load[I][J];
        spin(i, j) = mu * in.spin[I][J];
        aL(i, j) = shortening[I][J];
        K(i, j) = EI * in.bending[I][J];
        D(i, j) = 0;
      }
    }
    for (int i = 0; i < 2; ++i) D(i, i) = 2 * modal_damping * std::sqrt(K(i, i) * mass(i, i));
    mass_minus_spin = mass - spin;
    // initial assembly, open branch (the model's parameters)
    const double Ax = a1 * std::cos(theta1_0), Ay = a1 * std::sin(theta1_0);
    const double dA = std::sqrt((a4 - Ax) * (a4 - Ax) + Ay * Ay), alpha = std::atan2(-Ay, a4 - Ax);
    theta2_0 = alpha + std::acos((a2 * a2 + dA * dA - a3 * a3) / (2 * a2 * dA));
    theta3_0 = alpha + M_PI - std::acos((a3 * a3 + dA * dA - a2 * a2) / (2 * a3 * dA));
  }

  State initial() const {
    State y = State::Zero();
    y(0) = theta1_0;
    y(1) = theta2_0 - theta1_0;
    y(4) = theta3_0;
    return y;
  }

  void rates(const State& y, State& dy) const {
    const double th1 = y(0), th2 = y(1), th4 = y(4), w1 = y(5), w2 = y(6), w4 = y(9), cur = y(10);
    const Vec2 eta = y.segment<2>(2), etad = y.segment<2>(7);
    // the section at A: psi = 2 atan(s / 2), written without atan
    const double s = slope_A.dot(eta), sd = slope_A.dot(etad), t = s / 2, c = 1 / (1 + t * t);
    const double cpsi = (1 - t * t) * c, spsi = 2 * t * c, psid = c * sd;
    const double c1 = std::cos(th1), s1 = std::sin(th1), c2 = std::cos(th2), s2 = std::sin(th2);
    const double c4 = std::cos(th4), s4 = std::sin(th4);
    const double ca = c2 * cpsi + s2 * spsi, sa = s2 * cpsi - c2 * spsi;  // alpha = th2 - psi
    const double cphi = c1 * ca - s1 * sa, sphi = s1 * ca + c1 * sa;    // phi = th1 + alpha
    const double alphad = w2 - psid, omega = w1 + alphad;
    const double Vx = a1 * sa * w1, Vy = a1 * ca * w1;  // A's velocity in the coupler's axes

    // The coupler's mass matrix on v = (Vx, Vy, omega, eta'), by its columns:
    //   V:      (m, 0, -sy, -load eta) and (0, m, sx, mean)
    //   omega:  (-sy, sx, Jzz, moment)
    //   eta'_k: (-(load eta)_k, mean_k, moment_k, mass(:, k))
    const Vec2 Le = load * eta, Led = load * etad, Sme = mass_minus_spin * eta;
    const double sx = m * L / 2 - 0.5 * eta.dot(Le), sy = mean.dot(eta);
    const double Jzz = J0 + eta.dot(Sme);
    // momenta p = M v
    const double pX = m * Vx - sy * omega - Le.dot(etad), pY = m * Vy + sx * omega + mean.dot(etad);
    // M' v, the gyroscopic terms (omega x p_V, V x p_V), -dT/deta, elastic and damping forces
    const double dsy = mean.dot(etad), dsx = -eta.dot(Led), dJzz = 2 * eta.dot(mass_minus_spin * etad);
    double fX = -dsy * omega - Led.dot(etad) - omega * pY;
    double fY = dsx * omega + omega * pX;
    double fW = -dsy * Vx + dsx * Vy + dJzz * omega + Vx * pY - Vy * pX;
    const Vec2 dT_deta = -mean * (Vx * omega) - Le * (Vy * omega) + Sme * (omega * omega) - Led * Vx;
    Vec2 fE = -Led * Vx - dT_deta + K * eta + D * etad;
    // v = J qc' with qc = (th1, th2, eta1, eta2): th1' moves A (u = a1 (sin alpha, cos alpha)
    // in the coupler's axes) and turns the frame, th2' turns it, eta'_k bends it and turns
    // it by -c phi_k'(0). M J' qc' (J' qc' = (bx, by, bw, 0, 0)) joins the bias.
    const double ux = a1 * sa, uy = a1 * ca, k1 = -c * slope_A(0), k2 = -c * slope_A(1);
    const double bx = uy * alphad * w1, by = -ux * alphad * w1, bw = t * c * c * sd * sd;
    fX += m * bx - sy * bw;
    fY += m * by + sx * bw;
    fW += -sy * bx + sx * by + Jzz * bw;
    fE += -Le * bx + mean * by + moment * bw;
    // M J, column by column (5-vectors as (X, Y, W, E); the th1 column's E part is not needed)
    const double Mj0X = m * ux - sy, Mj0Y = m * uy + sx, Mj0W = -sy * ux + sx * uy + Jzz;
    const double Mj2X = -Le(0) - sy * k1, Mj2Y = mean(0) + sx * k1, Mj2W = moment(0) + Jzz * k1;
    const Vec2 Mj2E = mass.col(0) + moment * k1;
    const double Mj3X = -Le(1) - sy * k2, Mj3Y = mean(1) + sx * k2, Mj3W = moment(1) + Jzz * k2;
    const Vec2 Mj3E = mass.col(1) + moment * k2;
    // J^T M J (+ the crank's I1) and -J^T f + the motor's torque: J^T x = (ux xX + uy xY + xW, xW, k1 xW + xE1, k2 xW + xE2)
    Eigen::Matrix4d A;
    A(0, 0) = I1 + ux * Mj0X + uy * Mj0Y + Mj0W;
    A(1, 0) = Mj0W, A(1, 1) = Jzz;
    A(2, 0) = ux * Mj2X + uy * Mj2Y + Mj2W, A(2, 1) = Mj2W, A(2, 2) = k1 * Mj2W + Mj2E(0);
    A(3, 0) = ux * Mj3X + uy * Mj3Y + Mj3W, A(3, 1) = Mj3W, A(3, 2) = k1 * Mj3W + Mj3E(0), A(3, 3) = k2 * Mj3W + Mj3E(1);
    const double torque = K_m * cur - D_shaft * w1;
    Eigen::Matrix<double, 4, 3> rhs;  // columns: the forces, then the cut joint's directions Gc^T
    rhs(0, 0) = torque - (ux * fX + uy * fY + fW);
    rhs(1, 0) = -fW;
    rhs(2, 0) = -(k1 * fW + fE(0));
    rhs(3, 0) = -(k2 * fW + fE(1));

    // the cut joint at B: g = B_rocker - B_coupler (world), its Jacobian G and G' q'
    const Vec2 aLe = aL * eta;
    const double l = L - 0.5 * eta.dot(aLe), ld = -aLe.dot(etad), ldd0 = -etad.dot(aL * etad);
    const Vec2 e(cphi, sphi), n(-sphi, cphi);
    Eigen::Matrix<double, 2, 4> Gc;
    Gc.col(0) = -a1 * Vec2(-s1, c1) - l * n;
    Gc.col(1) = -l * n;
    Gc.col(2) = aLe(0) * e + l * c * slope_A(0) * n;
    Gc.col(3) = aLe(1) * e + l * c * slope_A(1) * n;
    const Vec2 G4 = a3 * Vec2(-s4, c4);
    const Vec2 g = Vec2(a4 + a3 * c4, a3 * s4) - Vec2(a1 * c1, a1 * s1) - l * e;
    const Eigen::Vector4d qcd(w1, w2, etad(0), etad(1));
    const Vec2 gd = Gc * qcd + G4 * w4;
    const double phidd0 = t * c * c * sd * sd;
    const Vec2 Gdqd = -a3 * w4 * w4 * Vec2(c4, s4) -
                      (-a1 * w1 * w1 * Vec2(c1, s1) + (ldd0 - l * omega * omega) * e + (2 * ld * omega + l * phidd0) * n);
    const Vec2 gamma = -Gdqd - 2 * kStabilisation * gd - kStabilisation * kStabilisation * g;

    // multipliers by the Schur complement: A [x0 Y] = [f Gc^T] (A's lower triangle),
    // (Gc Y + G4 G4^T / I3) lambda = gamma - Gc x0
    rhs.rightCols<2>() = Gc.transpose();
    ldlt_solve(A, rhs);
    const Eigen::Vector4d x0 = rhs.col(0);
    const Eigen::Matrix<double, 4, 2> Y = rhs.rightCols<2>();
    const Mat2 S = Gc * Y + G4 * G4.transpose() / I3;
    const Vec2 lambda = S.inverse() * (gamma - Gc * x0);
    const Eigen::Vector4d qcdd = x0 + Y * lambda;

    dy.head<5>() = y.segment<5>(5);
    dy.segment<4>(5) = qcdd;
    dy(9) = G4.dot(lambda) * (1 / I3);
    dy(10) = (V_supply - R_a * cur - K_m * w1) / L_a;
  }

  Outputs outputs(const State& y) const {
    return {y(5), y(9), y(10), shape_mid.dot(y.segment<2>(2)), y(2), y(3)};
  }

  /// The state at kTEnd_s from the assembly at rest, RK4 with `steps` steps.
  State run(long steps) const {
    State y = initial(), k1, k2, k3, k4;
    const double h = kTEnd_s / static_cast<double>(steps);
    for (long k = 0; k < steps; ++k) {
      rates(y, k1);
      rates(y + h / 2 * k1, k2);
      rates(y + h / 2 * k2, k3);
      rates(y + h * k3, k4);
      y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    return y;
  }
};

using bench_modal::fastest_of;

/// The hand-written rates and the generated model's derivative, each under
/// bench::rk4 to kTEnd_s with `steps` steps: omega_crank at the end.
double hand_under_rk4(const ByHand& model, long steps) {
  const State y0 = model.initial();
  std::vector<double> y(y0.data(), y0.data() + y0.size());
  bench::rk4(
      [&](double, const double* x, double* xdot) {
        State dy;
        model.rates(Eigen::Map<const State>(x), dy);
        Eigen::Map<State> out(xdot);
        out = dy;
      },
      y, kTEnd_s / static_cast<double>(steps), steps);
  return y[5];
}
double generated_under_rk4(crank_rocker_flexible_model::crank_rocker_flexible_model& model, long steps) {
  std::vector<double> y(model.size());
  model.initial(0.0, y.data(), nullptr);
  bench::rk4([&](double t, const double* x, double* xdot) { model.derivative(t, x, xdot); }, y,
             kTEnd_s / static_cast<double>(steps), steps);
  std::vector<double> out(8);
  model.outputs(kTEnd_s, y.data(), nullptr, out.data());
  return out[0];  // omega_crank
}

/// One run of the generated simulator to kTEnd_s under RK4 with `steps`
/// steps: the outputs there and the run's wall time (its summary).
struct SimResult {
  Outputs out{NAN, NAN, NAN, NAN, NAN, NAN};
  double wall_s = NAN;
};
SimResult run_simulator(const std::string& sim, long steps) {
  const bench_modal::GeneratedRun run = bench_modal::run_generated(sim, kTEnd_s, steps, "crank_rocker_flexible_by_hand");
  SimResult r;
  // columns: t,omega_crank,omega_rocker,current,force_j1,axial_force,deflection_mid,eta1,eta2
  const std::vector<double>& c = run.last_row;
  if (c.size() == 9) r.out = {c[1], c[2], c[3], c[6], c[7], c[8]};
  r.wall_s = run.wall_s;
  return r;
}

void print_row(const char* what, const Outputs& o) {
  std::printf("  %-28s %.12f %.12f %.12f %.6e %.6e %.6e\n", what, o.omega_crank, o.omega_rocker, o.current,
              o.deflection_mid, o.eta1, o.eta2);
}
double largest_difference(const Outputs& a, const Outputs& b) {
  return std::max({std::abs(a.omega_crank - b.omega_crank), std::abs(a.omega_rocker - b.omega_rocker),
                   std::abs(a.current - b.current), std::abs(a.deflection_mid - b.deflection_mid),
                   std::abs(a.eta1 - b.eta1), std::abs(a.eta2 - b.eta2)});
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: crank_rocker_flexible_by_hand PATH/TO/bench_crank_rocker_flexible\n");
    return 2;
  }
  const ByHand model;
  const long ref_steps = 1L << 18, same_steps = 1L << 12;
  const Outputs ref_hand = model.outputs(model.run(ref_steps));
  const SimResult ref_sim = run_simulator(argv[1], ref_steps);
  const Outputs same_hand = model.outputs(model.run(same_steps));
  const SimResult same_sim = run_simulator(argv[1], same_steps);

  // Each against its own reference: the largest step 2^-k within kTarget on omega_crank.
  long steps = 1L << 6;
  while (!(std::abs(model.outputs(model.run(steps)).omega_crank - ref_hand.omega_crank) <= kTarget) && steps < ref_steps)
    steps *= 2;
  const double hand_s = fastest_of([&] { volatile double v = model.run(steps)(5); (void)v; });
  long sim_steps = 1L << 6;
  SimResult sim = run_simulator(argv[1], sim_steps);
  while (!(std::abs(sim.out.omega_crank - ref_sim.out.omega_crank) <= kTarget) && sim_steps < ref_steps) {
    sim_steps *= 2;
    sim = run_simulator(argv[1], sim_steps);
  }
  double sim_s = sim.wall_s;
  for (int rep = 0; rep < 9; ++rep) sim_s = std::min(sim_s, run_simulator(argv[1], sim_steps).wall_s);
  // In process, one RK4 loop, each at its own step count: the ratio to the target.
  crank_rocker_flexible_model::crank_rocker_flexible_model generated;
  const double same_loop_check = generated_under_rk4(generated, sim_steps);  // = the simulator's, to rounding
  const double hand_loop_s = std::min(hand_s, fastest_of([&] { volatile double v = hand_under_rk4(model, steps); (void)v; }));
  const double gen_loop_s = fastest_of([&] { volatile double v = generated_under_rk4(generated, sim_steps); (void)v; });

  std::printf("flexible crank-rocker, 2 pinned-pinned modes, geometric stiffness, 1 %% damping: outputs at t = %g s\n", kTEnd_s);
  std::printf("  %-28s %-14s %-14s %-14s %-12s %-12s %s\n", "", "omega_crank", "omega_rocker", "current", "deflection_mid",
              "eta1", "eta2");
  print_row("by hand (RK4, 2^-18 s)", ref_hand);
  print_row("mbgc (RK4, 2^-18 s)", ref_sim.out);
  std::printf("  largest difference %.2g\n", largest_difference(ref_hand, ref_sim.out));
  print_row("by hand (RK4, 2^-12 s)", same_hand);
  print_row("mbgc (RK4, 2^-12 s)", same_sim.out);
  std::printf("  largest difference %.2g (the same step: the same discrete solution)\n",
              largest_difference(same_hand, same_sim.out));
  std::printf("error in omega_crank at t = %g s against each one's own 2^-18 s reference, rad/s:\n", kTEnd_s);
  std::printf("  %-8s %-12s %s\n", "steps", "by hand", "mbgc");
  auto error = [](double x, double ref) {
    char buf[32];
    if (std::isfinite(x)) std::snprintf(buf, sizeof buf, "%.2e", std::abs(x - ref));
    else std::snprintf(buf, sizeof buf, "blows up");
    return std::string(buf);
  };
  for (long k = 1L << 8; k <= (1L << 13); k *= 2)
    std::printf("  %-8ld %-12s %s\n", k, error(model.outputs(model.run(k)).omega_crank, ref_hand.omega_crank).c_str(),
                error(run_simulator(argv[1], k).out.omega_crank, ref_sim.out.omega_crank).c_str());
  std::printf("to %g rad/s on omega_crank:\n", kTarget);
  std::printf("  by hand: RK4, %ld steps, %.3g s\n", steps, hand_s);
  std::printf("  mbgc:    RK4, %ld steps, %.3g s  (%.2fx; the generated simulator's own run summary, fastest of ten\n"
              "           fresh processes)\n",
              sim_steps, sim_s, sim_s / hand_s);
  std::printf("in this process, one RK4 loop (bench/peers/rk4.hpp), the fastest of repeated runs:\n");
  std::printf("  by hand: %ld steps, %.3g s (the faster of its own Eigen loop and this one)\n", steps, hand_loop_s);
  std::printf("  mbgc:    %ld steps, %.3g s  (%.2fx the hand-written model's time; omega_crank %.12f, the simulator's %.12f)\n",
              sim_steps, gen_loop_s, gen_loop_s / hand_loop_s, same_loop_check, sim.out.omega_crank);
  return 0;
}
