#include "work_precision.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "integrator.hpp"
#include "report.hpp"
#include "trial_run.hpp"

namespace mbgrt::detail {

namespace {

constexpr double kLoosestRtol = 1e-3, kTightestRtol = 1e-10;
constexpr int kStepHalvings = 8;  // a fixed-step method's steps: interval / 1 ... interval / 128

std::string field(double x) { return x > 0 ? fmt::format("{:.3g}", x) : std::string(); }
std::string count(long x) { return x >= 0 ? fmt::format("{}", x) : std::string(); }
/// The energy witness's residual of a run that reached its end; empty without one.
std::string energy_field(const TrialRun& run) {
  if (!run.ok || run.energy_residual < 0) return {};
  return fmt::format("{:.3g}", run.energy_residual);
}

}  // namespace

std::vector<Trial> sweep_for(const Model& model, const Settings& base) {
  const double ratio = atol_per_rtol(base);
  std::vector<Trial> trials;
  // Every integrator made for the model's form (an ODE is not swept with a
  // DAE integrator, which would only add a Newton iteration): fixed-step
  // ones at halved steps, adaptive ones over the tolerances.
  const ModelForm form = model.is_dae() ? ModelForm::dae : ModelForm::ode;
  for (const IntegratorInfo& i : kIntegrators) {
    if (i.form != form || !why_integrator_does_not_fit(i, model).empty()) continue;
    if (!i.adaptive) {
      for (int k = 0; k < kStepHalvings; ++k) trials.push_back({i.solver, 0, 0, base.interval_s / std::pow(2.0, k)});
      continue;
    }
    for (double rtol = kLoosestRtol; rtol >= kTightestRtol * 0.99; rtol /= 10)
      trials.push_back({i.solver, rtol, rtol * ratio, 0});
  }
  return trials;
}

int work_precision(Model& model, const Options& o, OutputFile& out) {
  const Settings base = o.settings;
  const std::size_t outputs = model.output_names().size();
  const double ratio = atol_per_rtol(base);

  const Reference reference = find_reference(model, base);
  const TrialRun& ref = reference.run;
  const Settings& ref_settings = reference.settings;
  const double floor = reference.floor;
  if (!ref.ok) {
    print_error(fmt::format("--work-precision: the reference run ({} down to rtol 1e-10) {}",
                            solver_name(ref_settings.solver), ref.failure));
    return kExitRunFailed;
  }

  out.write("solver,rtol,atol,step_s,wall_s,steps,rhs_evals,fd_jac_rhs_evals,jac_evals,max_rel_error,energy_residual,status\n");
  // the reference's row: its error is the floor (its difference from a run at 10 x its rtol)
  out.write(fmt::format("reference,{},{},,{:.6g},{},{},,,{},{},\"{} (error: against rtol {:g})\"\n", field(ref_settings.rtol),
                        field(ref_settings.atol), ref.wall_s, ref.stats.steps, ref.stats.rhs_evals,
                        std::isfinite(floor) ? fmt::format("{:.6g}", floor) : std::string("inf"), energy_field(ref),
                        solver_name(ref_settings.solver), 10 * ref_settings.rtol));
  if (!o.quiet)
    fmt::print(stderr,
               "mbgrt: work-precision for model '{}', {} s, interval {} s (no step is longer);\n"
               "  reference {} at rtol {:g}, its own error about {:.1e} (against rtol {:g})\n"
               "{:>7} {:>9} {:>9} {:>10} {:>8} {:>9}  {}\n",
               model.name(), base.t_end_s - base.t_start_s, base.interval_s, solver_name(ref_settings.solver),
               ref_settings.rtol, floor, 10 * ref_settings.rtol, "solver", "rtol", "step_s", "wall_s", "steps", "error",
               "status");
  for (const Trial& trial : sweep_for(model, base)) {
    Settings s = base;
    s.solver = trial.solver;
    if (!integrator_info(trial.solver).adaptive) s.step_s = trial.step_s;
    else s.rtol = trial.rtol, s.atol = trial.atol;
    const TrialRun run = run_timed(model, s);
    const double error = max_rel_error(run, ref, outputs, ratio);
    std::string status = run.ok ? "ok" : run.failure;
    std::replace(status.begin(), status.end(), '"', '\'');  // it is written as one quoted CSV field
    out.write(fmt::format("{},{},{},{},{:.6g},{},{},{},{},{},{},\"{}\"\n", solver_name(trial.solver), field(trial.rtol),
                          field(trial.atol), field(trial.step_s), run.wall_s, run.stats.steps, run.stats.rhs_evals,
                          count(run.stats.fd_jac_evals), count(run.stats.jac_evals),
                          std::isfinite(error) ? fmt::format("{:.6g}", error) : std::string("inf"), energy_field(run),
                          status));
    if (!o.quiet)
      fmt::print(stderr, "{:>7} {:>9} {:>9} {:>10.4g} {:>8} {:>9.2e}  {}\n", solver_name(trial.solver), field(trial.rtol),
                 field(trial.step_s), run.wall_s, run.stats.steps, error, status);
  }
  return kExitSuccess;
}

}  // namespace mbgrt::detail
