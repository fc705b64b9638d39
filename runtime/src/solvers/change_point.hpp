// solvers/change_point.hpp — stepping an index-2 DAE across a change point.
//
// Where a mechanism's loops change branch (IFToMM's parallelogram four-bar
// with its links aligned), rows of the constraints' Jacobian G become
// dependent for an instant. IDA's Newton matrix then has a singular value
// that passes through zero and changes sign: a Newton iteration set up on one
// side diverges on the other, IDA cuts its step towards 1e-13 s around the
// crossing and stops (IDA_CONV_FAIL or IDA_ERR_FAIL). The motion itself is
// smooth there: only the multipliers along the dependent rows are
// undetermined, while the force they apply (G' lambda) stays finite.
//
// So the integrator steps over the crossing instead of through it: classical
// Runge-Kutta steps on the states, each stage's rates the DAE's in its
// index-1 form (consistent_initial_values with mu = 0: a minimum-norm solve,
// which tolerates the dependent rows), from the last point IDA completed to
// beyond the crossing; each step's end is put back on the constraints
// (assemble) and IDA restarts at the last. A projection rather than
// minimum-norm multipliers inside BDF, because it keeps IDA's Newton
// iteration off the singular matrix altogether, and rather than rows dropped
// while dependent, because a dropped row loses the finite force it applies
// for as long as it is dropped.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "constraints.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// The least independence of the lagrange rows at (t, y): the smallest part
/// of a kept row's (equilibrated) gradient that the rows before it do not
/// explain (find_redundant_constraints), 0 where a row was found dependent;
/// `row`, if given, the position row where that is (the first found dependent).
double row_independence(Model& model, const ConstraintShape& shape, double t, const double* y,
                        std::size_t* row = nullptr);

/// The Runge-Kutta steps across a change point, from (t0, y0, yp0) where IDA
/// stopped, to about five times as far as the crossing is from there, or to
/// t_limit if the run ends before (its last steps are then these); each
/// step's end assembled to rounding (IDA restarts there, with tolerances
/// that may ask for less than assembly's own test: measured, atol 1e-12 on a
/// row of 10 four-bars failed its first step after a restart otherwise).
class ChangePointStep {
 public:
  /// Plans and takes the steps: empty (and `why` says why) unless the rows
  /// at y0 are close to dependent (below 0.3 of `start_independence`),
  /// or if a stage has no consistent rates (a loop that cannot close).
  static std::optional<ChangePointStep> plan(Model& model, const ConstraintShape& shape, double start_independence,
                                             double t0, const double* y0, const double* yp0, double t_limit,
                                             std::string& why);

  double from() const { return path_.front().t; }
  double to() const { return path_.back().t; }
  double independence() const { return rho0_; }
  /// The position row least independent where the steps began.
  std::size_t row() const { return row_; }

  /// The state at t in [from(), to()] (assembled, with consistent y' and
  /// multipliers); `energy` (two integrals) gains the energy witness's
  /// power from from() to t.
  bool state_at(double t, double* y, double* yp, double* energy, std::string& why) const;

 private:
  struct Point {
    double t;
    std::vector<double> y, yp;
    double energy[2];  // the witness's integrals since from()
  };
  ChangePointStep(Model& model, const ConstraintShape& shape) : model_(&model), shape_(&shape) {}
  /// Consistent y' and multipliers at y (first put on the constraints, at a
  /// step's end; a stage is taken as it is, as in any Runge-Kutta method).
  bool rates(double t, std::vector<double>& y, std::vector<double>& yp, bool on_constraints, std::string& why) const;
  /// Steps of at most kLongestStep from path.back() to t, appended to path.
  bool march(double t, std::vector<Point>& path, std::string& why) const;

  Model* model_;
  const ConstraintShape* shape_;
  double rho0_ = 0.0;
  std::size_t row_ = 0;
  std::vector<Point> path_;  // the steps' ends
};

}  // namespace mbgrt::detail
