// solvers/carry_across.hpp — an implicit method's change points of the cut
// joints, left to dopri5.
//
// In joint coordinates, where a loop closed by cut joints changes branch
// (IFToMM's parallelogram four-bar with its links aligned), the cut joints'
// rows become dependent for an instant. The ODE stays defined there
// (derivative()'s rank-revealing solve takes minimum-norm multipliers), but
// BDF's corrector, solving for the end of a step, can converge on the other
// branch of motion without failing a test (measured on a row of four
// four-bars under CVODE at rtol 1e-8: 0.02 m off over 10 s, the other
// branch for one). An explicit method only evaluates the model and steps
// across. So an implicit method (cvode, ida on an ODE) watches the cut
// joints' independence with a root function, and where it falls to a tenth
// of the start's hands the run to dopri5 at the same tolerances until the
// joints are four times as independent beyond the crossing; then it
// restarts there. (Runge-Kutta steps of its own, as IDA takes across its
// lagrange rows' change points, were measured worse: stages close to the
// crossing get multipliers amplified by one over the pivot, which dopri5's
// error control sees and fixed steps do not.)
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "guard.hpp"
#include "integrator.hpp"

namespace mbgrt::detail {

/// The independence of the model's cut joints at (t, y): the square root of
/// their multipliers' systems' smallest pivot over their largest entry
/// (RankLossLog::latest_closest), which falls as the square of the distance
/// to a crossing, so this linearly; 0 where a solve lost rank, 1 where the
/// model has none. One evaluation of the model's own derivative (a probe:
/// the run's checks report what goes wrong in the run), into `scratch`.
double cut_joint_independence(GuardedModel& model, double t, const double* y, std::vector<double>& scratch);

class CarryAcross {
 public:
  /// Watches the cut joints of an ODE from (t0, y0); active() unless the
  /// model has none or they are dependent at the start (then a run near a
  /// change point is warned, simulate.cpp).
  CarryAcross(GuardedModel& model, const Settings& s, double t0, const double* y0);

  bool active() const { return watch_below_ > 0.0; }
  /// The root function: the independence at (t, y) less the watch's level
  /// (falling through 0: a change point ahead).
  double root(double t, const double* y) { return cut_joint_independence(model_, t, y, scratch_) - watch_below_; }

  /// dopri5 takes over at (t, y), with the energy witness's integrals
  /// `energy` there (two, or null).
  void begin(double t, const double* y, const double* energy);
  bool carrying() const { return static_cast<bool>(dopri5_); }
  /// dopri5 on to t_out, in steps of kProbe, writing t, y and energy, until
  /// the joints are independent again (then carrying() turns false and its
  /// counts are added to `counted`) or t_out is reached. False, with
  /// `failure` set, if dopri5 fails.
  bool carry(double t_out, double& t, double* y, double* energy, SolverStats& counted, SolverFailure& failure);

  /// The spans dopri5 carried, from and to (s); the open one up to t.
  std::vector<std::pair<double, double>> spans(double t) const;
  /// For the summary's solver line: "; across N change points ..." or empty.
  std::string describe(double t) const;
  /// The counts of an open span (what carry() adds when it ends).
  void add_open_counts(SolverStats& st) const;

 private:
  // dopri5 takes over once the cut joints' independence falls to this share
  // of the start's (as IDA steps across its lagrange rows' change points)
  // and hands back where it is kBeyond times that beyond the crossing, but
  // not above kHighestTarget of the start's (the start need not be the most
  // independent place), measured every kProbe (s).
  static constexpr double kWatchFrom = 0.1;
  static constexpr double kBeyond = 4.0;
  static constexpr double kHighestTarget = 0.9;
  static constexpr double kSmallestIndependence = 1e-3;
  static constexpr double kProbe = 2.5e-3;
  static constexpr std::size_t kListed = 4;  ///< spans named in the summary

  GuardedModel& model_;
  Settings settings_;
  double start_ = 1.0;        ///< the independence at the start
  double watch_below_ = 0.0;  ///< the root's level (0: not watched)
  std::vector<double> scratch_;
  std::unique_ptr<Integrator> dopri5_;  ///< while it carries the run
  double from_ = 0.0;
  double energy_[2] = {0.0, 0.0};  ///< the witness's integrals where dopri5 took over
  double last_ = 0.0, target_ = 0.0;
  std::vector<std::pair<double, double>> spans_;
};

}  // namespace mbgrt::detail
