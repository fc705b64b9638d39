// --work-precision: the speed/accuracy trade of one model, measured. The
// simulator runs itself with every integrator that fits the model over a
// range of tolerances (adaptive methods) or step sizes (rk4), measures each
// run's error against a reference run at a much tighter tolerance, and
// writes one CSV row per run:
//
//   solver,rtol,atol,step_s,wall_s,steps,rhs_evals,fd_jac_rhs_evals,jac_evals,max_rel_error,energy_residual,status
//
// max_rel_error is the largest |y - y_ref| over every output and output time,
// each output scaled by its largest |y_ref|, but by no less than the model's
// atol / rtol (an output that stays near zero is measured at that scale).
// energy_residual is the energy witness's largest |residual| over the run, in
// J (energy_witness.hpp: an error estimate that needs no reference); empty
// for a model without an energy balance or a run that failed.
// A run that fails has error `inf` and the reason in `status`; no row holds NaN.
#pragma once

#include <string>
#include <vector>

#include "cli.hpp"
#include "csv.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// One setting of the sweep: an adaptive solver's rtol (atol follows it in
/// the model's own atol/rtol ratio) or rk4's step.
struct Trial {
  Solver solver = kDefaultOdeSolver;
  double rtol = 0, atol = 0, step_s = 0;
};

/// The settings the sweep runs for a model: rk4 over steps interval / 2^k,
/// dopri5 and cvode over rtol 1e-3 ... 1e-10 for an ODE; ida alone for a DAE.
std::vector<Trial> sweep_for(const Model& model, const Settings& base);

/// Runs the sweep and writes the CSV to `out`; a table to stderr unless quiet.
/// Exit status 0, or kExitRunFailed if even the reference run fails.
int work_precision(Model& model, const Options& o, OutputFile& out);

}  // namespace mbgrt::detail
