// Hand-written models with joint constraints, standing in for what mbgc
// generates for `constraints = lagrange` and `constraints = penalty`.
#pragma once

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "models.hpp"

namespace mbgrt::test {

/// Point mass m in the plane: position (x, y), velocity (u, v), gravity g0 in
/// -y. Holonomic constraints g_i(x, y) = 0 with gradients G_i = (gx_i, gy_i);
/// gdot_i = gx_i u + gy_i v. Row 0 is the rod of a pendulum,
/// g = (x^2 + y^2 - L^2) / 2 ("rod.g[0]"); with `with_wall`, row 1 is a wall
/// g = x - wall ("wall.g[0]"); the default wall = 2 is out of reach of a rod
/// of length 1.
class PlanarMass : public TestModel {
 public:
  explicit PlanarMass(bool with_wall) : k_(with_wall ? 2 : 1) {
    param("m", 1.0);
    param("L", 1.0);
    param("g0", 9.81);
    param("x0", 1.0);  // released horizontally from rest by default
    param("y0", 0.0);
    param("u0", 0.0);
    param("v0", 0.0);
    param("wall", 2.0);
  }

  std::string constraint_name(std::size_t i) const override {
    const bool velocity = i >= k_;
    const std::size_t row = velocity ? i - k_ : i;
    return std::string(row == 0 ? "rod" : twin_ ? "twin" : "wall") + (velocity ? ".gdot[0]" : ".g[0]");
  }
  std::size_t position_constraint_count() const override { return k_; }
  std::size_t velocity_constraint_count() const override { return k_; }
  void constraints(double, const double* s, double* c) override {
    for (std::size_t i = 0; i < k_; ++i) {
      double gx = 0.0, gy = 0.0;
      c[i] = g(i, s[0], s[1], gx, gy);
      c[k_ + i] = gx * s[2] + gy * s[3];
    }
  }
  /// x and y are positions, u and v velocities; the multipliers of a DAE
  /// (lambda_0..k-1, then mu_0..k-1) follow the states.
  UnknownRole unknown_role(std::size_t i) const override {
    if (i < 4) return i < 2 ? UnknownRole::position : UnknownRole::velocity;
    return i - 4 < k_ ? UnknownRole::multiplier : UnknownRole::stabiliser;
  }
  /// G: every row reads x and y.
  void constraint_jacobian_pattern(std::vector<long>& row_starts, std::vector<long>& columns) const override {
    row_starts.clear();
    columns.clear();
    for (std::size_t i = 0; i < k_; ++i) {
      row_starts.push_back(static_cast<long>(columns.size()));
      columns.insert(columns.end(), {0, 1});
    }
    row_starts.push_back(static_cast<long>(columns.size()));
  }
  void constraint_jacobian(double, const double* s, double* values) override {
    for (std::size_t i = 0; i < k_; ++i) g(i, s[0], s[1], values[2 * i], values[2 * i + 1]);
  }

 protected:
  /// g_i at (x, y), and its gradient.
  double g(std::size_t i, double x, double y, double& gx, double& gy) const {
    if (i == 0) {
      gx = x;
      gy = y;
      return 0.5 * (x * x + y * y - p("L") * p("L"));
    }
    if (twin_) {  // the rod again, scaled: implied by row 0
      gx = 2.0 * x;
      gy = 2.0 * y;
      return x * x + y * y - p("L") * p("L");
    }
    gx = 1.0;
    gy = 0.0;
    return x - p("wall");
  }
  void initial_state(double* s) const {
    s[0] = p("x0");
    s[1] = p("y0");
    s[2] = p("u0");
    s[3] = p("v0");
  }
  std::string state_name(std::size_t i) const {
    static const char* const names[] = {"mass.x", "mass.y", "mass.u", "mass.v"};
    return names[i];
  }

  std::size_t k_;       ///< number of constraints
  bool twin_ = false;   ///< row 1 is 2 x row 0 (a redundant constraint) instead of the wall
};

/// Lagrange twin: the stabilised index-2 DAE of Gear, Gupta and Leimkuhler,
/// y = [x, y, u, v, lambda_0..k-1, mu_0..k-1]:
///   x' - u - sum gx_i mu_i = 0        y' - v - sum gy_i mu_i = 0
///   u' + sum gx_i lambda_i / m = 0    v' + sum gy_i lambda_i / m + g0 = 0
///   gdot_i = 0 (rows of lambda)       g_i = 0 (rows of mu)
/// lambda is the rod tension per unit length (m (u^2 + v^2 - g0 y) / L^2 on
/// the constraint manifold); mu vanishes on the exact solution.
class GglPendulum : public PlanarMass {
 public:
  explicit GglPendulum(bool with_wall = false) : PlanarMass(with_wall) {
    param("poison_after", 1e300);  // the gdot row turns NaN after this time
    settings.t_end_s = 1.0;
    settings.interval_s = 0.05;
    settings.solver = Solver::ida;
    settings.rtol = 1e-10;
    settings.atol = 1e-12;
  }
  const char* name() const override { return "ggl_pendulum"; }
  std::size_t size() const override { return 4 + 2 * k_; }
  std::size_t state_count() const override { return 4; }
  bool constraints_enforced() const override { return true; }
  bool is_dae() const override { return true; }
  void differential_ids(double* id) const override {
    for (std::size_t i = 0; i < size(); ++i) id[i] = i < 4 ? 1.0 : 0.0;
  }
  std::string variable_name(std::size_t i) const override {
    if (i < 4) return state_name(i);
    const std::size_t j = i - 4;
    const std::size_t row = j % k_;
    return std::string(row == 0 ? "rod" : "wall") + (j < k_ ? ".lambda" : ".mu");
  }
  long multiplier_index(std::size_t row) const override { return row < k_ ? long(4 + row) : -1; }
  long stabiliser_index(std::size_t row) const override { return row < k_ ? long(4 + k_ + row) : -1; }
  std::vector<std::string> output_names() const override {
    return {"x", "y", "u", "v", "lambda", "mu", "xdot", "udot", "vdot"};
  }
  void initial(double, double* y, double* yp) override {
    initial_state(y);
    for (std::size_t i = 4; i < size(); ++i) y[i] = 0.0;  // multipliers: any guess
    for (std::size_t i = 0; i < size(); ++i) yp[i] = 0.0;
  }
  void residual(double t, const double* y, const double* yp, double* r) override {
    const double m = p("m");
    r[0] = yp[0] - y[2];
    r[1] = yp[1] - y[3];
    r[2] = yp[2];
    r[3] = yp[3] + p("g0");
    for (std::size_t i = 0; i < k_; ++i) {
      double gx = 0.0, gy = 0.0;
      const double gi = g(i, y[0], y[1], gx, gy);
      const double lambda = y[4 + i], mu = y[4 + k_ + i];
      r[0] -= gx * mu;
      r[1] -= gy * mu;
      r[2] += gx * lambda / m;
      r[3] += gy * lambda / m;
      r[4 + i] = gx * y[2] + gy * y[3];
      r[4 + k_ + i] = gi;
    }
    if (t > p("poison_after")) r[4] = std::nan("");
  }
  void outputs(double, const double* y, const double* yp, double* out) override {
    for (int i = 0; i < 4; ++i) out[i] = y[i];
    out[4] = y[4];
    out[5] = y[4 + k_];
    out[6] = yp ? yp[0] : std::nan("");
    out[7] = yp ? yp[2] : std::nan("");
    out[8] = yp ? yp[3] : std::nan("");
  }
};

/// The pendulum with its rod constraint stated twice (row 1 = 2 x row 0), as
/// a planar loop of revolute joints in 3-D states some rows twice: the
/// Newton matrix of the DAE is singular unless the runtime finds row 1
/// redundant and holds its multipliers at 0. `hide_multipliers` makes the
/// model withhold where they are (as a model compiled before
/// multiplier_index() existed): the runtime must refuse it.
class TwinRodPendulum : public GglPendulum {
 public:
  explicit TwinRodPendulum(bool hide_multipliers = false) : GglPendulum(true), hide_(hide_multipliers) {
    twin_ = true;
  }
  long multiplier_index(std::size_t row) const override {
    return hide_ ? -1 : GglPendulum::multiplier_index(row);
  }
  long stabiliser_index(std::size_t row) const override {
    return hide_ ? -1 : GglPendulum::stabiliser_index(row);
  }

 private:
  bool hide_;
};

/// Penalty twin: an ODE in (x, y, u, v); each constraint is a stiff
/// spring-damper along its gradient, force -G_i (k g_i + c gdot_i) with
/// c = 2 sqrt(k m) (about critical for the stretch of a unit rod).
class PenaltyPendulum : public PlanarMass {
 public:
  explicit PenaltyPendulum(double stiffness = 1e6, bool with_wall = false)
      : PlanarMass(with_wall) {
    param("k", stiffness);
    settings.t_end_s = 1.0;
    settings.interval_s = 0.05;
    settings.solver = Solver::cvode;
    settings.rtol = 1e-8;
    settings.atol = 1e-10;
  }
  const char* name() const override { return "penalty_pendulum"; }
  std::size_t size() const override { return 4; }
  std::string variable_name(std::size_t i) const override { return state_name(i); }
  std::vector<std::string> output_names() const override { return {"x", "y", "u", "v"}; }
  void initial(double, double* y, double*) override { initial_state(y); }
  void derivative(double, const double* s, double* ds) override {
    const double m = p("m"), k = p("k"), c = 2.0 * std::sqrt(k * m);
    ds[0] = s[2];
    ds[1] = s[3];
    ds[2] = 0.0;
    ds[3] = -p("g0");
    for (std::size_t i = 0; i < k_; ++i) {
      double gx = 0.0, gy = 0.0;
      const double gi = g(i, s[0], s[1], gx, gy);
      const double force = k * gi + c * (gx * s[2] + gy * s[3]);
      ds[2] -= gx * force / m;
      ds[3] -= gy * force / m;
    }
  }
  void outputs(double, const double* y, const double*, double* out) override {
    for (int i = 0; i < 4; ++i) out[i] = y[i];
  }
};

/// Arithmetic-geometric mean.
inline double agm(double a, double b) {
  for (int i = 0; i < 64 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double next = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = next;
  }
  return a;
}

/// Exact period of a pendulum of length L released from rest at theta0:
/// T = 2 pi sqrt(L / g) / AGM(1, cos(theta0 / 2)).
inline double pendulum_period(double L, double g0, double theta0) {
  return 2.0 * std::numbers::pi * std::sqrt(L / g0) / agm(1.0, std::cos(theta0 / 2.0));
}

}  // namespace mbgrt::test
