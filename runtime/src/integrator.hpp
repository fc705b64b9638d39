// The interface every integrator implements, so the run loop, the CSV writer
// and the report never need to know which method is underneath.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "guard.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// Counters for the run summary. A counter a method does not have is -1 and
/// is left out of the summary rather than printed as a misleading zero.
struct SolverStats {
  long steps = 0;
  long rhs_evals = 0;      ///< RHS (ODE) or residual (DAE) evaluations by the method
  long fd_jac_evals = -1;  ///< extra evaluations spent on finite-difference Jacobians
  long jac_evals = -1;
  long nonlin_iters = -1;
  long nonlin_conv_fails = -1;
  long err_test_fails = -1;
  double last_step = 0.0;
  long warnings = 0;  ///< solver warnings (e.g. "t + h = t"), kept out of stderr
  std::string first_warning;
  long position_evals = -1;  ///< evaluations of the position rates alone (Model::position_rates)
};

/// Why an integrator gave up.
struct SolverFailure {
  double t = 0.0;              ///< time of the last successful internal step
  std::string flag_name;       ///< e.g. "CV_TOO_MUCH_WORK"
  std::string explanation;     ///< plain English
  std::string solver_message;  ///< the library's own message (captured, not printed by it)
  int suspect = -1;            ///< unknown with the largest weighted local error estimate (-1: unknown)
};

class Integrator {
 public:
  virtual ~Integrator() = default;

  virtual const char* name() const = 0;         ///< as spelled on --solver
  virtual std::string description() const = 0;  ///< method details for the summary

  /// Starts at (t0, y0[, yp0]). yp0 is only read for DAE models. May correct
  /// the initial values (IDA computes consistent ones). False on failure.
  virtual bool init(double t0, const double* y0, const double* yp0) = 0;

  /// Integrates to exactly t_out (never beyond the stop time), or, while the
  /// model's events pause (Events::pause_at_events), to the first instant
  /// inside where events fire, if there is one: t() says where it stopped.
  /// False on failure.
  virtual bool advance_to(double t_out) = 0;

  virtual double t() const = 0;
  virtual const double* y() const = 0;
  /// y' at t() for DAE models, null otherwise.
  virtual const double* yp() const { return nullptr; }

  /// The energy witness's two integrals at t() (GuardedModel::has_energy_witness):
  /// [0] the energy the sources supplied, [1] the energy the rest absorbed,
  /// since the start (J); null when the method does not carry them.
  virtual const double* energy() const { return nullptr; }

  virtual SolverStats stats() const = 0;
  virtual const SolverFailure& failure() const = 0;
  /// The unknowns whose tolerance the rounding floor set (ErrorWeights::floored); none for fixed steps.
  virtual std::vector<std::size_t> floored_unknowns() const { return {}; }
  /// The spans [from, to] (s) across a change point of the cut joints that
  /// an implicit method left to an explicit one (cvode to dopri5); none for
  /// the others.
  virtual std::vector<std::pair<double, double>> steps_across() const { return {}; }
  /// Where an adaptive method loosened the asked tolerances, which the
  /// model's arithmetic could not meet there (ida), for the rest of the run:
  /// from t_s on rtol and atol, in time order; none for the others.
  struct Loosening {
    double t_s, rtol, atol;
  };
  virtual std::vector<Loosening> loosenings() const { return {}; }
};

/// The events a root finder reported at (t, y) (root_info[k]: +1 rising,
/// -1 falling, 0 none) switched and logged; y may jump (Model::event_jump). False, with `failure` set, when the
/// modes chatter (Events::chattering).
bool fire_events(Events& events, double t, double* y, const std::vector<int>& root_info, SolverFailure& failure);
/// The same for one event located by a method without a root finder.
bool chatter_failure(const Events& events, double t, SolverFailure& failure);
/// st += before, counter by counter (counters a method lacks, -1, add nothing):
/// what a method counted before a restart zeroed its counters.
void add_counts(SolverStats& st, const SolverStats& before);

/// Settings::t_end_s is used as the stop time the integrator never steps past.
std::unique_ptr<Integrator> make_euler(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_heun(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_symplectic_euler(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_rk4(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_linearly_implicit_euler(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_ros2(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_generalized_alpha(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_dopri5(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_cvode(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_ida(GuardedModel& model, const Settings& s);
std::unique_ptr<Integrator> make_integrator(GuardedModel& model, const Settings& s);

const char* solver_name(Solver s);
/// Why integrator i cannot run `model` (a DAE for an ODE method, a model
/// without the position/velocity layout for symplectic_euler); empty if it can.
std::string why_integrator_does_not_fit(const IntegratorInfo& i, const Model& model);

}  // namespace mbgrt::detail
