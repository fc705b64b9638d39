// rotating_beam_by_hand — the rotating beam of examples/rotating_beam (thesis
// §9.3) written by hand in its modal form, against the simulator mbgc
// generates from the model.
//
// In the frame that turns with the hub, a cantilever's in-plane bending
// v(x, t) = sum phi_i(x) eta_i(t), with the centrifugal tension's geometric
// stiffness (thesis eq. 3.50), obeys, per unit rho A and with the shapes
// normalised so that int phi_i phi_j = L delta_ij,
//   L eta'' + [(EI / rho A) K + Omega^2 (S - L I)] eta = -Omega' m,
// K_ij = int phi_i'' phi_j'', S_ij = int (L^2 - x^2)/2 phi_i' phi_j',
// m_i = int x phi_i. The integrals come from the compiler's own beam code
// (compiler/flex/beam_modes), the rest is 2n first-order equations under
// RK4. The hub follows eq. 9.18's spin-up.
//
// Printed: the tip deflection at t = 8 s from both (they must agree: the
// same equations), and the wall time each needs for 1e-6 m there.
//   rotating_beam_by_hand PATH/TO/rotating_beam [modes = 3]
#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_rotating_beam_model.hpp"
#include "by_hand.hpp"
#include "flex/beam_modes.hpp"
#include "rk4.hpp"

namespace {

constexpr double kLength_m = 8, kDensity = 2766.67, kE = 6.8952e10, kWidth_m = 3.675e-2, kHeight_m = 1.986e-3;
constexpr double kOmegaS = 2, kTs = 15, kT_s = 8;  // final spin, spin-up time, when the tip is read
constexpr double kTarget_m = 1e-6;

struct Spin {
  double omega, omega_dot;
};
Spin hub(double t) {  // eq. 9.18
  const double c = kTs / (2 * M_PI);
  if (t >= kTs) return {kOmegaS, 0};
  return {kOmegaS / kTs * (t - c * std::sin(t / c)), kOmegaS / kTs * (1 - std::cos(t / c))};
}

struct ByHand {
  int n;
  Eigen::MatrixXd K, S;
  Eigen::VectorXd m, tip;
  double ei_over_rho_a;

  explicit ByHand(int modes) : n(modes) {
    const mbgc::flex::BeamModes shapes(mbgc::flex::Supports::ClampedFree, kLength_m, modes);
    const mbgc::flex::ModalIntegrals in = mbgc::flex::modal_integrals(shapes);
    K.resize(n, n), S.resize(n, n), m.resize(n), tip.resize(n);
    for (int i = 0; i < n; ++i) {
      m(i) = in.moment[static_cast<std::size_t>(i)];
      tip(i) = shapes.shape(i, kLength_m);
      for (int j = 0; j < n; ++j) {
        K(i, j) = in.bending[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
        S(i, j) = in.spin[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      }
    }
    const double area = kWidth_m * kHeight_m, second_moment = kHeight_m * kWidth_m * kWidth_m * kWidth_m / 12;
    ei_over_rho_a = kE * second_moment / (kDensity * area);
  }

  void rates(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) const {
    const Spin s = hub(t);
    const Eigen::VectorXd eta = y.head(n), rate = y.tail(n);
    dy.head(n) = rate;
    dy.tail(n) = -(ei_over_rho_a * K * eta + s.omega * s.omega * (S * eta - kLength_m * eta) + s.omega_dot * m) / kLength_m;
  }

  /// Tip deflection at kT_s from rest, RK4 with `steps` steps.
  double tip_at_end(long steps) const {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * n), k1(2 * n), k2(2 * n), k3(2 * n), k4(2 * n);
    const double h = kT_s / static_cast<double>(steps);
    for (long k = 0; k < steps; ++k) {
      const double t = h * static_cast<double>(k);
      rates(t, y, k1);
      rates(t + h / 2, y + h / 2 * k1, k2);
      rates(t + h / 2, y + h / 2 * k2, k3);
      rates(t + h, y + h * k3, k4);
      y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    return tip.dot(y.head(n));
  }
};

using bench_modal::fastest_of;

/// The hand-written rates and the generated model's derivative, each under
/// bench::rk4 to kT_s with `steps` steps: the tip deflection at the end.
double hand_under_rk4(const ByHand& beam, long steps) {
  const int n2 = 2 * beam.n;
  std::vector<double> y(static_cast<std::size_t>(n2), 0.0);
  Eigen::VectorXd x(n2), dx(n2);
  bench::rk4(
      [&](double t, const double* in, double* out) {
        x = Eigen::Map<const Eigen::VectorXd>(in, n2);
        beam.rates(t, x, dx);
        Eigen::Map<Eigen::VectorXd>(out, n2) = dx;
      },
      y, kT_s / static_cast<double>(steps), steps);
  return beam.tip.dot(Eigen::Map<const Eigen::VectorXd>(y.data(), beam.n));
}
double generated_under_rk4(rotating_beam_model::rotating_beam_model& model, long steps) {
  std::vector<double> y(model.size());
  model.initial(0.0, y.data(), nullptr);
  bench::rk4([&](double t, const double* x, double* xdot) { model.derivative(t, x, xdot); }, y,
             kT_s / static_cast<double>(steps), steps);
  std::vector<double> out(3);
  model.outputs(kT_s, y.data(), nullptr, out.data());
  return out[1];  // tip_deflection
}

/// One run of the generated simulator to t = 8 s under RK4 with `steps`
/// steps (the hand-written model's integrator): the tip there and the run's
/// wall time (its summary).
struct SimResult {
  double tip = NAN, wall_s = NAN;
};
SimResult run_simulator(const std::string& sim, long steps) {
  const bench_modal::GeneratedRun run = bench_modal::run_generated(sim, kT_s, steps, "rotating_beam_by_hand");
  SimResult r;
  if (run.last_row.size() > 2) r.tip = run.last_row[2];  // columns: t,spin,tip_deflection,eta1
  r.wall_s = run.wall_s;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: rotating_beam_by_hand PATH/TO/rotating_beam [modes]\n");
    return 2;
  }
  const int modes = argc > 2 ? std::atoi(argv[2]) : 3;
  const ByHand beam(modes);
  // The hand-written model: its reference, then the largest step within 1e-6 m of it.
  const double ref_hand = beam.tip_at_end(1L << 20);
  long steps = 1L << 6;
  while (std::abs(beam.tip_at_end(steps) - ref_hand) > kTarget_m) steps *= 2;
  const double hand_s = fastest_of([&] { volatile double v = beam.tip_at_end(steps); (void)v; });
  // The generated simulator (joint coordinates: an ODE of the same six
  // states), under the same RK4: its reference, then the largest step within
  // 1e-6 m of it, timed by its own run summary (best of three).
  const SimResult ref_sim = run_simulator(argv[1], 1L << 18);
  long sim_steps = 1L << 6;
  SimResult sim = run_simulator(argv[1], sim_steps);
  while (!(std::abs(sim.tip - ref_sim.tip) <= kTarget_m) && sim_steps < (1L << 18)) {
    sim_steps *= 2;
    sim = run_simulator(argv[1], sim_steps);
  }
  double sim_s = sim.wall_s;
  for (int rep = 0; rep < 2; ++rep) sim_s = std::min(sim_s, run_simulator(argv[1], sim_steps).wall_s);
  // In process, one RK4 loop, each at its own step count: the ratio to the target.
  rotating_beam_model::rotating_beam_model generated;
  const double same_loop_check = generated_under_rk4(generated, sim_steps);  // = the simulator's, to rounding
  const double hand_loop_s = std::min(hand_s, fastest_of([&] { volatile double v = hand_under_rk4(beam, steps); (void)v; }));
  const double gen_loop_s = fastest_of([&] { volatile double v = generated_under_rk4(generated, sim_steps); (void)v; });

  std::printf("rotating beam, %d modes, Omega_s = %g rad/s: tip deflection at t = %g s\n", modes, kOmegaS, kT_s);
  std::printf("  by hand (RK4, 2^-20 of 8 s): %.9f m\n", ref_hand);
  std::printf("  mbgc (RK4, 2^-18 of 8 s):    %.9f m   difference %.2g m\n", ref_sim.tip, std::abs(ref_sim.tip - ref_hand));
  std::printf("to 1e-6 m:\n");
  std::printf("  by hand: RK4, %ld steps, %.3g s\n", steps, hand_s);
  std::printf("  mbgc:    RK4, %ld steps, %.3g s  (%.2fx; the generated simulator's own run summary, fastest of three\n"
              "           fresh processes)\n",
              sim_steps, sim_s, sim_s / hand_s);
  std::printf("in this process, one RK4 loop (bench/peers/rk4.hpp), the fastest of repeated runs:\n");
  std::printf("  by hand: %ld steps, %.3g s (the faster of its own Eigen loop and this one)\n", steps, hand_loop_s);
  std::printf("  mbgc:    %ld steps, %.3g s  (%.2fx the hand-written model's time; tip %.12f m, the simulator's %.12f m)\n",
              sim_steps, gen_loop_s, gen_loop_s / hand_loop_s, same_loop_check, sim.tip);
  return 0;
}
