// trial_run.hpp — runs of a model kept in memory and measured against a
// reference: what --work-precision (work_precision.hpp) and --accuracy
// (accuracy.hpp) are made of. A trial writes nothing and reports nothing;
// its outputs at every output time, its cost and why it stopped are kept.
#pragma once

#include <string>
#include <vector>

#include "integrator.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// What one run produced: every output at every output time, and its cost.
struct TrialRun {
  bool ok = false;
  std::string failure;          ///< why it stopped, when !ok
  double wall_s = 0;            ///< the fastest of its repeats
  SolverStats stats;
  std::vector<double> outputs;  ///< row-major: output times x outputs
  double energy_residual = -1;  ///< the energy witness's largest |residual| (J); -1: the model has none
};

/// The run with settings `s`, from the model's initial state, with the
/// energy witness on.
TrialRun run_once(Model& model, const Settings& s);
/// The run, repeated while it is short (the fastest repeat's time counts:
/// the others were slowed by something else on the machine).
TrialRun run_timed(Model& model, const Settings& s);

/// max over outputs and times of |y - y_ref| / max(max_t |y_ref|, noise_scale)
/// (inf if the run stopped early or produced a non-finite value). The floor
/// keeps an output that stays near zero (a drift, a conserved component)
/// from being measured relative to its own rounding noise.
double max_rel_error(const TrialRun& run, const TrialRun& ref, std::size_t outputs, double noise_scale);

/// The model's own atol / rtol: every run keeps it, and it is the scale below
/// which an output counts as near zero.
double atol_per_rtol(const Settings& s);

/// The most accurate run that goes through, as a reference: Dormand-Prince
/// at rtol 1e-13 for an ODE (a BDF method's global error on a long
/// oscillatory run stays far above its rtol), then the implicit solver at
/// 1e-12 ... 1e-10. Its own error is estimated from a second run at 10 x
/// its rtol: the floor below which measured errors mean nothing.
struct Reference {
  TrialRun run;       ///< !run.ok if none went through (the last one's failure)
  Settings settings;  ///< the reference's
  double floor = 0;   ///< its own error (inf if none went through)
};
Reference find_reference(Model& model, const Settings& base);
/// The same from `rtol` on (Dormand-Prince; the implicit solver from
/// 100 x rtol): a reference as accurate as a measurement needs, and cheaper.
Reference find_reference(Model& model, const Settings& base, double rtol);

}  // namespace mbgrt::detail
