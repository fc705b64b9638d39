// The single door through which integrators call the model. It turns a
// non-finite number (or a stray exception) into a recorded "blame" and an
// unrecoverable error code, so the run stops at the first bad value with the
// time and the variable that caused it instead of marching on with NaNs.
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <limits>
#include <vector>

#include "constraints.hpp"
#include "events.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// Where the first non-finite value was seen.
enum class BlameSite { derivative, residual, state, exception, limit, constraint };

struct Blame {
  double t = 0.0;
  BlameSite site = BlameSite::state;
  std::size_t index = 0;  ///< unknown (or equation) index into y; BlameSite::constraint: the position row
  double value = 0.0;     ///< the offending value (NaN, +Inf or -Inf)
  std::string detail;     ///< exception text for BlameSite::exception
  /// A value became NaN or infinite (not an exception, a limit or a joint row).
  bool non_finite() const {
    return site == BlameSite::derivative || site == BlameSite::residual || site == BlameSite::state;
  }
};

class GuardedModel {
 public:
  explicit GuardedModel(Model& model);

  Model& model() { return model_; }
  const Model& model() const { return model_; }
  std::size_t size() const { return n_; }
  bool is_dae() const { return dae_; }
  /// 1.0 for differential unknowns, 0.0 for algebraic ones (all 1.0 for ODEs).
  const std::vector<double>& differential_ids() const { return ids_; }
  /// Sizes of the model's joint constraints (none for most models).
  const ConstraintShape& constraint_shape() const { return shape_; }
  /// Lagrange rows whose multipliers residual() holds at 0 (redundant rows).
  void set_redundant_constraints(std::vector<std::size_t> rows) { shape_.redundant = std::move(rows); }

  /// When derivative() checks that y is finite: before calling the model
  /// (SUNDIALS' stage values), or only to place the blame once ydot is not
  /// (rk4, whose stage values are checked states plus finite multiples of
  /// checked derivatives: the check would cost a pass over y per call).
  enum class InputCheck { before, on_failure };

  /// SUNDIALS convention: 0 on success, -1 (unrecoverable) after recording a blame.
  /// With `rate` (the witness on), also the model's powers there, as power()
  /// gives them, from the same evaluation (Model::derivative_and_power).
  int derivative(double t, const double* y, double* ydot, InputCheck check = InputCheck::before,
                 double* rate = nullptr);
  int residual(double t, const double* y, const double* yp, double* r);
  /// The energy witness (Model::has_energy_balance), for the runs that
  /// report it: the integrators made after this call carry the integrals of
  /// the model's two powers beside the state (CVODES' and IDAS' quadratures,
  /// outside the error test; the explicit methods' own stages) and give them
  /// at each output point (Integrator::energy). False if the model has none.
  bool enable_energy_witness() {
    witness_ = model_.has_energy_balance();
    if (witness_) events_.count_jumped_energy();
    return witness_;
  }
  bool has_energy_witness() const { return witness_; }
  /// rate[0..2) = the model's power at (t, y; yp for a DAE, else null):
  /// supplied, then absorbed (W). A power that is not finite counts as 0:
  /// the witness fails, never the run (witness_broken_at says when). Returns 0.
  int power(double t, const double* y, const double* yp, double* rate);
  /// A power that is not finite counts as 0 from t on (witness_broken_at).
  void keep_finite(double t, double* rate);
  /// The first time the power was not finite; NaN if it always was.
  double witness_broken_at() const { return witness_broken_at_; }

  /// ydot's position entries (Model::position_rates, where the model gives
  /// them; else the whole derivative); -1 after recording a blame. As
  /// derivative() with InputCheck::on_failure: y is checked only to place
  /// the blame.
  int position_rates(double t, const double* y, double* ydot);

  /// The model's own Jacobian (row-major n x n); -1 after recording a blame.
  int jacobian(double t, const double* y, double* J);
  bool has_jacobian() const { return model_.has_jacobian() && !dae_ && !finite_differences_; }
  /// --fd-jacobian: ignore the model's Jacobian (to measure what it saves).
  void use_finite_differences() { finite_differences_ = true; }

  /// Checks y after a step; false (and a recorded blame) if any entry is
  /// non-finite or a state is beyond the limit of its model's validity.
  bool check_state(double t, const double* y);
  /// At an output point: false (and a recorded blame) if a position row is
  /// violated beyond its bound (hold_constraints; true until that is called).
  bool check_constraints(double t, const double* y);
  /// Bounds for check_constraints: |g| <= bound for every position row the
  /// model holds (Model::constraint_held), <= penalty_bound for the others
  /// (a penalty's): beyond them, the joints cannot all hold (a loop that
  /// cannot close) and the run must stop.
  void hold_constraints(double bound, double penalty_bound);
  /// Whether position row r must hold (Model::constraint_held), once hold_constraints ran.
  bool row_held(std::size_t r) const { return r < held_.size() && held_[r]; }

  /// The model's events (none for most models): modes, switches, their log.
  Events& events() { return events_; }
  const Events& events() const { return events_; }

  /// The first recorded problem; later ones are consequences and are ignored.
  const std::optional<Blame>& blame() const { return blame_; }

  /// "state 'x' became NaN (derivative non-finite)" and the like.
  std::string describe(const Blame& b) const;

 private:
  int record(double t, BlameSite site, std::size_t index, double value, std::string detail = {});
  /// `evaluate` (which fills ydot from y) guarded: an exception, or a
  /// non-finite entry of ydot (blamed on y where y is not finite), is recorded.
  template <class Evaluate>
  int rates(double t, const double* y, const double* ydot, Evaluate&& evaluate);
  /// Index of the first non-finite entry of v[0..n), or n if all are finite.
  std::size_t first_non_finite(const double* v) const;

  Model& model_;
  std::size_t n_;
  bool witness_ = false;
  double witness_broken_at_;
  bool dae_;
  std::vector<double> ids_;
  std::vector<double> limits_;  ///< Model::state_limit per unknown (HUGE_VAL: none)
  std::vector<double> bounds_;  ///< the limits, kLargest for none (a check in one loop)
  static constexpr double kLargest = std::numeric_limits<double>::max();  ///< the largest finite double
  double bound_of(std::size_t row) const { return held_[row] ? held_bound_ : penalty_bound_; }
  std::vector<char> held_;    ///< per position row: Model::constraint_held
  std::vector<double> rows_;  ///< the rows' values (Model::constraints)
  double held_bound_ = HUGE_VAL, penalty_bound_ = HUGE_VAL;
  ConstraintShape shape_;
  std::optional<Blame> blame_;
  bool finite_differences_ = false;
  Events events_;
};

}  // namespace mbgrt::detail
