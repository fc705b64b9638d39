#include "trial_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "energy_witness.hpp"
#include "guard.hpp"
#include "march.hpp"
#include "report.hpp"

namespace mbgrt::detail {

namespace {

constexpr double kMinTrialTime_s = 0.2;  // repeat a short run until this much wall time has passed
constexpr int kMaxRepeats = 5;

}  // namespace

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

double atol_per_rtol(const Settings& s) { return s.rtol > 0 ? s.atol / s.rtol : 1.0; }

Reference find_reference(Model& model, const Settings& base) { return find_reference(model, base, 1e-13); }

Reference find_reference(Model& model, const Settings& base, double rtol) {
  const std::size_t outputs = model.output_names().size();
  const double ratio = atol_per_rtol(base);
  struct Candidate { Solver solver; double rtol; };
  std::vector<Candidate> candidates;
  const ModelForm form = model.is_dae() ? ModelForm::dae : ModelForm::ode;
  for (const IntegratorInfo& i : kIntegrators)
    if (i.form == form && i.adaptive && !i.implicit) candidates.push_back({i.solver, rtol});
  for (const IntegratorInfo& i : kIntegrators)
    if (i.form == form && i.adaptive && i.implicit)
      for (double r : {10 * rtol, 100 * rtol, 1000 * rtol}) candidates.push_back({i.solver, r});
  Reference ref{{}, base, std::numeric_limits<double>::infinity()};
  for (const Candidate& c : candidates) {
    ref.settings.solver = c.solver;
    ref.settings.rtol = c.rtol;
    ref.settings.atol = c.rtol * ratio;
    ref.run = run_once(model, ref.settings);
    if (!ref.run.ok) continue;
    Settings looser = ref.settings;
    looser.rtol *= 10, looser.atol *= 10;
    ref.floor = max_rel_error(run_once(model, looser), ref.run, outputs, ratio);
    break;
  }
  return ref;
}

}  // namespace mbgrt::detail
