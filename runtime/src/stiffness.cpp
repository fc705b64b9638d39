#include "stiffness.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <vector>

namespace mbgrt::detail {

namespace {

double norm(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

}  // namespace

StiffnessEstimate estimate_stiffness(Model& model, double t, const double* x) {
  StiffnessEstimate e;
  e.t = t;
  if (model.is_dae()) return e;
  const std::size_t n = model.size();
  std::vector<double> f0(n), f1(n), xs(x, x + n), v(n), w(n);
  model.derivative(t, x, f0.data());
  double x_norm = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(f0[i]) || !std::isfinite(x[i])) return e;
    x_norm = std::max(x_norm, std::abs(x[i]));
  }
  // Start from the motion itself, f(x): the iteration then stays among the
  // modes the motion excites. A planar mechanism's out-of-plane modes (stiff
  // rows acting on a rod's tiny spin inertia) are exactly zero in every
  // state and cannot limit an explicit solver's step; a generic start
  // vector would find them. At rest (f = 0) any vector will do.
  v = f0;
  if (!(norm(v) > 0))
    for (std::size_t i = 0; i < n; ++i) v[i] = 1.0 + 0.1 * static_cast<double>(i % 7);
  // The geometric mean of the growth ||J v|| / ||v|| over the second half of
  // the iterations: it converges to |lambda_max| also when the dominant pair
  // is complex (an oscillation), where the direction never settles.
  constexpr int kIterations = 40;
  double log_sum = 0;
  int counted = 0;
  for (int k = 0; k < kIterations; ++k) {
    const double vn = norm(v);
    if (!(vn > 0) || !std::isfinite(vn)) return e;
    const double eps = std::sqrt(std::numeric_limits<double>::epsilon()) * (1.0 + x_norm) / vn;
    for (std::size_t i = 0; i < n; ++i) xs[i] = x[i] + eps * v[i];
    model.derivative(t, xs.data(), f1.data());
    for (std::size_t i = 0; i < n; ++i) w[i] = (f1[i] - f0[i]) / eps;
    const double growth = norm(w) / vn;
    if (!std::isfinite(growth)) return e;
    if (growth == 0) break;  // df/dx v = 0: nothing moves faster than this
    if (k >= kIterations / 2) log_sum += std::log(growth), ++counted;
    for (std::size_t i = 0; i < n; ++i) v[i] = w[i] / norm(w);
  }
  e.valid = true;
  e.rate_per_s = counted ? std::exp(log_sum / counted) : 0.0;
  return e;
}

double explicit_stability_bound(std::string_view solver) {
  if (solver == "rk4") return 2.78;
  if (solver == "dopri5") return 3.3;
  return 0.0;
}

std::string describe_stiffness(const StiffnessEstimate& e, std::string_view solver, double step_s,
                               bool penalty_joints) {
  if (!e.valid || !(e.rate_per_s > 0)) return {};
  std::string s = fmt::format("at t = {:.6g} s the model's fastest mode has a rate of {:.2g} 1/s (time scale {:.2g} s)",
                              e.t, e.rate_per_s, 1.0 / e.rate_per_s);
  if (const double bound = explicit_stability_bound(solver); bound > 0) {
    s += fmt::format("; {} is stable only for steps below about {:.2g} s", solver, bound / e.rate_per_s);
    if (step_s > 0) s += fmt::format(" (this run's: {:.2g} s)", step_s);
    s += ", whatever the accuracy asked for; an implicit solver (--solver cvode) is not bound by it";
  }
  if (penalty_joints)
    s += "; the penalty joints' stiffness sets such a rate: a lower `stiffness`, or constraints = lagrange, removes it";
  return s;
}

}  // namespace mbgrt::detail
