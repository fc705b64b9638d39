#include "march.hpp"

#include <cmath>

#include "messages.hpp"
#include "grid.hpp"

namespace mbgrt::detail {

namespace {

bool all_finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

Outcome march(GuardedModel& guard, Integrator& integrator, const Settings& s,
              const std::vector<double>& y0, const std::vector<double>& yp0,
              const std::function<void()>& on_point, const std::atomic<int>* stop) {
  Outcome r;
  // A NaN in the initial values would otherwise surface as an obscure first-step failure.
  if (!guard.check_state(s.t_start_s, y0.data())) return {false, false, false};
  r.started = true;
  // The modes of the model's steps from the state it starts in.
  if (!guard.events().start(s.t_start_s, y0.data(), yp0.empty() ? nullptr : yp0.data())) {
    print_error("an event function (the argument of a step) is not finite at the start");
    return {false, false, false};
  }
  r.solver_failed = !integrator.init(s.t_start_s, y0.data(), yp0.data());
  r.ok = !r.solver_failed;
  if (r.ok) on_point();

  const OutputGrid grid(s.t_start_s, s.t_end_s, s.interval_s);
  for (std::size_t k = 1; r.ok && k < grid.size(); ++k) {
    if (stop && (r.signal = stop->load()) != 0) break;
    r.solver_failed = !integrator.advance_to(grid[k]);
    r.ok = !r.solver_failed && guard.check_state(integrator.t(), integrator.y()) &&
           guard.check_constraints(integrator.t(), integrator.y());
    if (r.ok) on_point();
  }
  return r;
}

ConstrainedStart prepare_constrained_start(Model& model, GuardedModel& guard, double t0,
                                           std::vector<double>& y0, std::vector<double>& yp0) {
  ConstrainedStart start;
  const ConstraintShape& shape = guard.constraint_shape();
  if (!shape.any()) return start;
  if (std::string broken = contract_violation(model, shape, guard.differential_ids());
      !broken.empty()) {
    print_error(broken);
    start.ok = false;
    return start;
  }
  // A non-finite initial value is reported by the run loop, in model terms.
  if (!all_finite(y0)) return start;
  guard.events().start(t0, y0.data(), yp0.empty() ? nullptr : yp0.data());  // the residual below reads the modes
  start.assembly = assemble(model, shape, t0, y0.data());
  if (!start.assembly->ok) {
    print_error(start.assembly->error);
    start.ok = false;
    return start;
  }
  if (shape.dae) {
    RedundancyReport redundancy = find_redundant_constraints(model, shape, t0, y0.data());
    if (!redundancy.redundant.empty()) {
      guard.set_redundant_constraints(redundancy.redundant);
      start.redundancy = std::move(redundancy);
    }
    start.initial_values = consistent_initial_values(model, shape, t0, y0.data(), yp0.data());
    if (!start.initial_values->ok) {
      print_error(start.initial_values->error);
      start.ok = false;
    }
  }
  return start;
}

}  // namespace mbgrt::detail
