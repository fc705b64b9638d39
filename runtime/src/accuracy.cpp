#include "accuracy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "messages.hpp"
#include "integrator.hpp"
#include "trial_run.hpp"
#include "work_precision.hpp"

namespace mbgrt::detail {

namespace {

/// A setting as the summary names it: "rk4, step 0.0025 s", "cvode, rtol 1e-06".
std::string describe(const Settings& s) {
  if (integrator_info(s.solver).adaptive) return fmt::format("{}, rtol {:g}", solver_name(s.solver), s.rtol);
  return fmt::format("{}, step {:g} s", solver_name(s.solver), s.step_s);
}

struct Measured {
  Settings settings;
  double error;   ///< against the reference, its own error added
  double wall_s;  ///< the run's
};

}  // namespace

std::optional<AccuracyChoice> choose_for_accuracy(Model& model, const Settings& base, double tolerance) {
  const auto started = std::chrono::steady_clock::now();
  // a reference a thousand times finer than asked (at most 1e-6), tightened
  // by a factor of 100 while its own error is above a tenth of the request
  // (a compliant contact's impacts need it), down to 1e-13
  Reference reference;
  for (double rtol = std::clamp(tolerance / 1000, 1e-13, 1e-6);; rtol = std::max(rtol / 100, 1e-13)) {
    reference = find_reference(model, base, rtol);
    if (!reference.run.ok || reference.floor <= tolerance / 10 || rtol <= 1e-13) break;
  }
  if (!reference.run.ok) {
    print_error(fmt::format("--accuracy: the reference run ({} at rtol {:g}) {}", solver_name(reference.settings.solver),
                            reference.settings.rtol, reference.run.failure));
    return std::nullopt;
  }
  const std::size_t outputs = model.output_names().size();
  const double ratio = atol_per_rtol(base);

  // Each method's settings run from the cheapest (the longest step, the
  // loosest tolerance) on: once one meets the request, or costs more than
  // the best so far, the finer ones cannot be cheaper and are not run.
  std::vector<Measured> tried;
  auto cheapest_meeting = [&]() -> const Measured* {
    const Measured* best = nullptr;
    for (const Measured& m : tried)
      if (m.error <= tolerance && (!best || m.wall_s < best->wall_s)) best = &m;
    return best;
  };
  std::optional<Solver> done;  // the method whose finer settings cannot be cheaper
  for (const Trial& trial : sweep_for(model, base)) {
    if (done && trial.solver == *done) continue;
    done.reset();
    Settings s = base;
    s.solver = trial.solver;
    if (!integrator_info(trial.solver).adaptive) s.step_s = trial.step_s;
    else s.rtol = trial.rtol, s.atol = trial.atol;
    // (one run each: its wall time ranks it; a repeat would make the choice cost more than it saves)
    const TrialRun run = run_once(model, s);
    // (the reference's own error counts: a run cannot be shown closer to the truth than that)
    const double error = max_rel_error(run, reference.run, outputs, ratio) + reference.floor;
    tried.push_back({s, error, run.wall_s});
    const Measured* best = cheapest_meeting();
    if (tried.back().error <= tolerance || (best && tried.back().wall_s > best->wall_s)) done = trial.solver;
  }
  const Measured* best = cheapest_meeting();
  const double probe_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!best) {
    const auto closest = std::min_element(tried.begin(), tried.end(),
                                          [](const Measured& a, const Measured& b) { return a.error < b.error; });
    const bool any = closest != tried.end() && std::isfinite(closest->error);
    print_error(fmt::format(
        "--accuracy {:g}: no setting tried meets it; the most accurate, {}, reaches {:.2g} (against {} at rtol {:g}, "
        "whose own error is about {:.1g}); ask for {} or more, or choose --solver yourself",
        tolerance, any ? describe(closest->settings) : std::string("none"), any ? closest->error : HUGE_VAL,
        solver_name(reference.settings.solver), reference.settings.rtol, reference.floor,
        any ? fmt::format("{:.2g}", closest->error) : std::string("more")));
    return std::nullopt;
  }
  AccuracyChoice choice;
  choice.settings = best->settings;
  choice.note = fmt::format(
      "asked {:g}: chose {}, the cheapest of {} settings run over the whole run that meet it: {:.2g} against {} at "
      "rtol {:g} (whose own error, about {:.1g}, is counted in); the choice took {:.3g} s",
      tolerance, describe(best->settings), tried.size(), best->error, solver_name(reference.settings.solver),
      reference.settings.rtol, reference.floor, probe_wall_s);
  return choice;
}

}  // namespace mbgrt::detail
