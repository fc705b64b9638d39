// stiffness.hpp — how fast the fastest mode of an ODE model is at a state:
// the spectral radius of df/dx, estimated by power iteration on
// finite-difference Jacobian-vector products. The run summary and the stop
// message use it to say when an explicit solver's steps were bounded by
// stability rather than accuracy, and why a run stopped ("the penalty
// joints' stiffness sets a 2e5 1/s mode; rk4 is stable below 1.4e-5 s").
#pragma once

#include <string>
#include <string_view>

#include "integrator.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

struct StiffnessEstimate {
  bool valid = false;       ///< false for DAEs, or if the model gave non-finite values
  double t = 0.0;           ///< where it was estimated
  double rate_per_s = 0.0;  ///< |largest eigenvalue of df/dx|
};

/// 40 derivative evaluations at (t, x), starting from the direction f(t, x):
/// the fastest of the modes the motion excites. The model's derivative must be pure.
StiffnessEstimate estimate_stiffness(Model& model, double t, const double* x);

/// The step h below which an explicit method is stable on a real decaying
/// mode of rate r: h r <= bound (rk4 2.78, dopri5 3.3); 0 for implicit solvers.
double explicit_stability_bound(std::string_view solver);

/// A sentence for the user: the fastest rate, and (for an explicit solver)
/// its stability limit, compared with `step_s` when step_s > 0; with a
/// pointer to the penalty joints when the model has them.
std::string describe_stiffness(const StiffnessEstimate& e, std::string_view solver, double step_s,
                               bool penalty_joints);

/// For an explicit run that reached its end: a sentence if its mean step sat
/// near the stability limit of the fastest excited mode (empty otherwise, and
/// for implicit solvers).
std::string stability_limited_note(Model& model, const Integrator& integrator, double t_start_s, bool penalty_joints);

}  // namespace mbgrt::detail
