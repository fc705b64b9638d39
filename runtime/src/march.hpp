// What every kind of run shares (a simulation, a linearisation, each trial of
// a work-precision sweep): putting a constrained model into a consistent
// initial state, then starting the integrator and marching it over the
// output grid.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <vector>

#include "constraints.hpp"
#include "guard.hpp"
#include "integrator.hpp"

namespace mbgrt::detail {

struct Outcome {
  bool ok = true;
  bool started = false;        ///< init() was reached: the integrator holds the state
  bool solver_failed = false;  ///< the integrator gave up (vs. the runtime stopping it)
  int signal = 0;              ///< the stop signal that ended the march after a row (ok stays true)
};

/// Starts the integrator at s.t_start_s and marches it over the output grid,
/// calling `on_point` at every communication point reached. With `stop`
/// (interrupt.hpp's flag), a signal caught ends the march after the point
/// being written, so that output ends with a whole row.
Outcome march(GuardedModel& guard, Integrator& integrator, const Settings& s,
              const std::vector<double>& y0, const std::vector<double>& yp0,
              const std::function<void()>& on_point, const std::atomic<int>* stop = nullptr);

/// What the runtime does to the initial values of a model with joint
/// constraints before the integrator starts: assembly (all models), then y'
/// and the algebraic unknowns (DAEs). Errors are reported (print_error) here.
struct ConstrainedStart {
  std::optional<AssemblyReport> assembly;
  std::optional<RedundancyReport> redundancy;  ///< only when some rows are redundant
  std::optional<InitialValuesReport> initial_values;
  bool ok = true;
};

ConstrainedStart prepare_constrained_start(Model& model, GuardedModel& guard, double t0,
                                           std::vector<double>& y0, std::vector<double>& yp0);

}  // namespace mbgrt::detail
