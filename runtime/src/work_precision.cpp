#include "work_precision.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "energy_witness.hpp"
#include "guard.hpp"
#include "integrator.hpp"
#include "march.hpp"
#include "report.hpp"

namespace mbgrt::detail {

namespace {

constexpr double kLoosestRtol = 1e-3, kTightestRtol = 1e-10;
constexpr int kStepHalvings = 8;         // a fixed-step method's steps: interval / 1 ... interval / 128
constexpr double kMinTrialTime_s = 0.2;  // repeat a short run until this much wall time has passed
constexpr int kMaxRepeats = 5;

/// What one run produced: every output at every output time, and its cost.
struct TrialRun {
  bool ok = false;
  std::string failure;          ///< why it stopped, when !ok
  double wall_s = 0;            ///< the fastest of its repeats
  SolverStats stats;
  std::vector<double> outputs;  ///< row-major: output times x outputs
  double energy_residual = -1;  ///< the energy witness's largest |residual| (J); -1: the model has none
};

TrialRun run_once(Model& model, const Settings& s) {
  TrialRun run;
  GuardedModel guard(model);
  guard.enable_energy_witness();
  const std::size_t n = model.size(), m = model.output_names().size();
  std::vector<double> y0(n), yp0(model.is_dae() ? n : 0), row(m);
  model.initial(s.t_start_s, y0.data(), model.is_dae() ? yp0.data() : nullptr);
  if (!prepare_constrained_start(model, guard, s.t_start_s, y0, yp0).ok) {
    run.failure = "no consistent initial state";
    return run;
  }
  auto integrator = make_integrator(guard, s);
  EnergyWitness witness(guard);
  const auto started = std::chrono::steady_clock::now();
  const Outcome r = march(guard, *integrator, s, y0, yp0, [&] {
    model.outputs(integrator->t(), integrator->y(), integrator->yp(), row.data());
    run.outputs.insert(run.outputs.end(), row.begin(), row.end());
    witness.observe(integrator->t(), integrator->y(), integrator->yp(), integrator->energy());
  });
  if (witness.active()) run.energy_residual = witness.worst();
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  run.stats = integrator->stats();
  run.ok = r.ok;
  model.terminal(integrator->t(), integrator->y());
  if (!r.ok) {
    std::string why = r.solver_failed ? integrator->failure().flag_name
                      : guard.blame() ? guard.describe(*guard.blame())
                                      : std::string("stopped");
    run.failure = fmt::format("failed at t = {}: {}", format_time(integrator->t()), why);
  }
  return run;
}

/// The run, repeated while it is short (the fastest repeat's time counts:
/// the others were slowed by something else on the machine).
TrialRun run_timed(Model& model, const Settings& s) {
  TrialRun best = run_once(model, s);
  double total = best.wall_s;
  for (int k = 1; best.ok && k < kMaxRepeats && total < kMinTrialTime_s; ++k) {
    TrialRun again = run_once(model, s);
    total += again.wall_s;
    best.wall_s = std::min(best.wall_s, again.wall_s);
  }
  return best;
}

/// max over outputs and times of |y - y_ref| / max(max_t |y_ref|, noise_scale)
/// (inf if the run stopped early or produced a non-finite value). The floor
/// keeps an output that stays near zero (a drift, a conserved component)
/// from being measured relative to its own rounding noise.
double max_rel_error(const TrialRun& run, const TrialRun& ref, std::size_t outputs, double noise_scale) {
  if (!run.ok || run.outputs.size() != ref.outputs.size()) return std::numeric_limits<double>::infinity();
  if (outputs == 0) return 0.0;
  std::vector<double> scale(outputs, noise_scale);
  for (std::size_t k = 0; k < ref.outputs.size(); ++k)
    scale[k % outputs] = std::max(scale[k % outputs], std::abs(ref.outputs[k]));
  double worst = 0;
  for (std::size_t k = 0; k < ref.outputs.size(); ++k) {
    const double d = std::abs(run.outputs[k] - ref.outputs[k]) / (scale[k % outputs] > 0 ? scale[k % outputs] : 1.0);
    if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

/// The model's own atol / rtol: every run keeps it, and it is the scale below
/// which an output counts as near zero.
double atol_per_rtol(const Settings& s) { return s.rtol > 0 ? s.atol / s.rtol : 1.0; }

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

  // The reference: the most accurate run that goes through (Dormand-Prince
  // at rtol 1e-13 for an ODE: a BDF method's global error on a long
  // oscillatory run stays far above its rtol; then the implicit solver).
  // Its own error is estimated from a second run at 10 x its rtol: the floor
  // below which the measured errors mean nothing.
  struct Candidate { Solver solver; double rtol; };
  std::vector<Candidate> candidates;
  const ModelForm form = model.is_dae() ? ModelForm::dae : ModelForm::ode;
  for (const IntegratorInfo& i : kIntegrators)
    if (i.form == form && i.adaptive && !i.implicit) candidates.push_back({i.solver, 1e-13});
  for (const IntegratorInfo& i : kIntegrators)
    if (i.form == form && i.adaptive && i.implicit)
      for (double rtol : {1e-12, 1e-11, 1e-10}) candidates.push_back({i.solver, rtol});
  TrialRun ref;
  Settings ref_settings = base;
  double floor = std::numeric_limits<double>::infinity();
  for (const Candidate& c : candidates) {
    ref_settings.solver = c.solver;
    ref_settings.rtol = c.rtol;
    ref_settings.atol = c.rtol * ratio;
    ref = run_once(model, ref_settings);
    if (!ref.ok) continue;
    Settings looser = ref_settings;
    looser.rtol *= 10, looser.atol *= 10;
    floor = max_rel_error(run_once(model, looser), ref, outputs, ratio);
    break;
  }
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
