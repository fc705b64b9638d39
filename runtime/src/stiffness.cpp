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
  const IntegratorInfo* info = find_integrator(solver);
  return info ? info->stability_bound : 0.0;
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

std::string stability_limited_note(Model& model, const Integrator& integrator, double t_start_s, bool penalty_joints) {
  const double bound = explicit_stability_bound(integrator.name());
  const long steps = integrator.stats().steps;
  if (!(bound > 0) || steps <= 0 || model.is_dae()) return {};
  const StiffnessEstimate e = estimate_stiffness(model, integrator.t(), integrator.y());
  const double mean_step_s = (integrator.t() - t_start_s) / static_cast<double>(steps);
  // Near the limit: well below it the steps were set by accuracy; far above
  // it the fast mode cannot have been excited (the run would have blown up).
  const double h_rate = e.rate_per_s * mean_step_s;
  if (!e.valid || h_rate <= 0.25 * bound || h_rate >= 2 * bound) return {};
  return fmt::format("steps limited by stability, not accuracy (mean step {:.2g} s): {}", mean_step_s,
                     describe_stiffness(e, integrator.name(), 0.0, penalty_joints));
}

}  // namespace mbgrt::detail
