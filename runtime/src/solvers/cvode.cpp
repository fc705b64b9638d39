// cvode: variable-order BDF with Newton iterations and a dense direct linear
// solver — the default for stiff mechanical models. The Jacobian comes from
// the generated model when it has one (exact, and no extra RHS calls),
// otherwise from CVODE's finite differences. CVODES (CVODE with
// quadratures) carries the energy witness's integrals beside the state,
// outside Newton's iteration and the error test.
//
// In joint coordinates, where a loop closed by cut joints changes branch
// (IFToMM's parallelogram four-bar with its links aligned), the cut joints'
// rows become dependent for an instant. The ODE stays defined there
// (derivative()'s rank-revealing solve takes minimum-norm multipliers), but
// BDF's corrector, solving for the end of a step, can converge on the other
// branch of motion without failing a test (measured on a row of four
// four-bars at rtol 1e-8: 0.02 m off over 10 s, the other branch for one).
// An explicit method only evaluates the model and steps across. So CVODE
// watches the cut joints' independence, and where it falls to a tenth of the
// start's hands the run to dopri5 at the same tolerances until the joints
// are four times as independent beyond the crossing, then restarts there.
#include <cvodes/cvodes.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "solvers/sundials_util.hpp"

namespace mbgrt::detail {

namespace {

int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
  auto* m = static_cast<CallbackData*>(user_data)->model;
  return m->derivative(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

/// The energy witness's rates (CVODES' quadrature right-hand side).
int power(sunrealtype t, N_Vector y, N_Vector rate, void* user_data) {
  auto* m = static_cast<CallbackData*>(user_data)->model;
  return m->power(t, N_VGetArrayPointer(y), nullptr, N_VGetArrayPointer(rate));
}

/// The independence of the model's cut joints at (t, y): the square root of
/// their multipliers' systems' smallest pivot over their largest entry
/// (RankLossLog::latest_closest), which falls as the square of the distance
/// to a crossing, so this linearly; 1 where the model has none. One
/// derivative evaluation, into `scratch`.
double cut_joint_independence(GuardedModel& model, double t, const double* y, std::vector<double>& scratch) {
  const RankLossLog* log = model.model().rank_loss();
  if (!log) return 1.0;
  scratch.resize(model.size());
  try {  // the model's own (a probe, not the run's: its checks report what goes wrong in the run)
    model.model().derivative(t, y, scratch.data());
  } catch (...) {
    return 1.0;
  }
  return std::sqrt(std::max(0.0, log->latest_closest()));
}

/// The events' roots, then (if watched) the cut joints' independence
/// falling below CallbackData::watch_below: a change point ahead.
int roots(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) {
  auto* data = static_cast<CallbackData*>(user_data);
  GuardedModel& m = *data->model;
  const std::size_t k = m.events().count();
  if (k > 0 && !m.events().functions(t, N_VGetArrayPointer(y), nullptr, g)) return -1;
  if (data->watch_below > 0.0)
    g[k] = cut_joint_independence(m, t, N_VGetArrayPointer(y), data->scratch) - data->watch_below;
  return 0;
}

/// The model's row-major Jacobian copied into CVODE's column-major dense matrix.
int jacobian(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user_data, N_Vector tmp1, N_Vector,
             N_Vector) {
  auto* m = static_cast<CallbackData*>(user_data)->model;
  const std::size_t n = m->size();
  thread_local std::vector<double> row_major;
  row_major.resize(n * n);
  (void)tmp1;
  if (int flag = m->jacobian(t, N_VGetArrayPointer(y), row_major.data()); flag != 0) return flag;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      SM_ELEMENT_D(J, static_cast<sunindextype>(i), static_cast<sunindextype>(j)) = row_major[i * n + j];
  return 0;
}

class Cvode final : public Integrator {
 public:
  Cvode(GuardedModel& model, const Settings& s) : m_(model), s_(s), y_(model.size(), ctx_), energy_(2, ctx_) {}
  ~Cvode() override {
    CVodeFree(&mem_);
    if (ls_) SUNLinSolFree(ls_);
    if (A_) SUNMatDestroy(A_);
  }

  const char* name() const override { return "cvode"; }
  std::string description() const override {
    std::string across;
    if (const auto carried = steps_across(); !carried.empty()) {
      std::vector<std::string> spans;
      for (std::size_t k = 0; k < carried.size() && k < kListedCrossings; ++k)
        spans.push_back(fmt::format("t = {:.6g} to {:.6g} s", carried[k].first, carried[k].second));
      if (carried.size() > kListedCrossings)
        spans.push_back(fmt::format("and {} more", carried.size() - kListedCrossings));
      across = fmt::format("; across {} change point{} of the cut joints, where their rows became dependent, dopri5 "
                           "carried the run at the same tolerances: {}",
                           carried.size(), carried.size() == 1 ? "" : "s", fmt::join(spans, ", "));
    }
    return fmt::format("CVODE BDF, Newton, dense LU, {} Jacobian{}, rtol {:g}, atol {:g}",
                       m_.has_jacobian() ? "generated" : "finite-difference", across, s_.rtol, s_.atol);
  }

  bool init(double t0, const double* y0, const double*) override {
    const auto n = static_cast<sunindextype>(m_.size());
    std::copy(y0, y0 + m_.size(), y_.data());
    t_ = t0;
    mem_ = CVodeCreate(CV_BDF, ctx_);
    check_setup(mem_, "CVodeCreate");
    check_setup(CVodeSetErrHandlerFn(mem_, MessageSink::handler, &sink_), "CVodeSetErrHandlerFn",
                sink_);
    check_setup(CVodeInit(mem_, rhs, t0, y_.get()), "CVodeInit", sink_);
    data_ = CallbackData{&m_, ErrorWeights(m_.model(), s_.rtol, s_.atol), 0.0, {}};
    check_setup(CVodeSetUserData(mem_, &data_), "CVodeSetUserData", sink_);
    check_setup(CVodeWFtolerances(mem_, error_weights), "CVodeWFtolerances", sink_);
    check_setup(CVodeSetStopTime(mem_, s_.t_end_s), "CVodeSetStopTime", sink_);
    check_setup(CVodeSetMaxNumSteps(mem_, kMaxStepsPerOutput), "CVodeSetMaxNumSteps", sink_);
    // Like ACSL's MAXTERVAL: never step over more than one communication
    // interval, so an input that is zero at the start (a bump, a late step)
    // cannot be jumped over by an ever-growing step.
    check_setup(CVodeSetMaxStep(mem_, s_.interval_s), "CVodeSetMaxStep", sink_);
    A_ = SUNDenseMatrix(n, n, ctx_);
    check_setup(A_, "SUNDenseMatrix");
    ls_ = SUNLinSol_Dense(y_.get(), A_, ctx_);
    check_setup(ls_, "SUNLinSol_Dense");
    check_setup(CVodeSetLinearSolver(mem_, ls_, A_), "CVodeSetLinearSolver", sink_);
    if (m_.has_jacobian()) check_setup(CVodeSetJacFn(mem_, jacobian), "CVodeSetJacFn", sink_);
    // The events' zero crossings, and (cut joints) their independence
    // falling to a tenth of the start's: a change point ahead.
    const RankLossLog* log = m_.model().rank_loss();
    start_independence_ = cut_joint_independence(m_, t0, y0, data_.scratch);
    if (log && log->cut_joints_solved() && start_independence_ > 0.0)
      data_.watch_below = kWatchFrom * start_independence_;
    if (const std::size_t k = m_.events().count() + (data_.watch_below > 0.0 ? 1 : 0); k > 0) {
      check_setup(CVodeRootInit(mem_, static_cast<int>(k), roots), "CVodeRootInit", sink_);
      root_info_.assign(k, 0);
      if (data_.watch_below > 0.0) {
        std::vector<int> direction(k, 0);
        direction.back() = -1;  // only as the rows become dependent
        check_setup(CVodeSetRootDirection(mem_, direction.data()), "CVodeSetRootDirection", sink_);
      }
    }
    std::fill(energy_.data(), energy_.data() + 2, 0.0);
    if (m_.has_energy_witness()) check_setup(CVodeQuadInit(mem_, power, energy_.get()), "CVodeQuadInit", sink_);
    return true;
  }

  bool advance_to(double t_out) override {
    if (across_) {  // dopri5 carrying the run across a change point
      if (!carry_across(t_out)) return false;
      if (across_ || reached(t_, t_out)) return true;
    }
    int flag = solve(t_out);
    while (flag == CV_ROOT_RETURN) {
      CVodeGetRootInfo(mem_, root_info_.data());
      const std::size_t k = m_.events().count();
      const std::vector<int> events(root_info_.begin(), root_info_.begin() + static_cast<long>(k));
      if (std::any_of(events.begin(), events.end(), [](int r) { return r != 0; })) {
        // an event: switch its mode, restart there
        if (!fire_events(m_.events(), t_, y_.data(), events, failure_)) return false;
        restart();
      } else if (data_.watch_below > 0.0 && root_info_[k] != 0) {  // a change point ahead
        hand_over();
        if (!carry_across(t_out)) return false;
        if (across_) return true;
      }
      if (reached(t_, t_out)) return true;  // the event is at the communication point
      flag = solve(t_out);
    }
    if (flag < 0) {
      double t_now = t_;
      CVodeGetCurrentTime(mem_, &t_now);
      failure_ = make_failure(t_now, CVodeGetReturnFlagName(flag), sink_);
      SerialVector ele(m_.size(), ctx_), w(m_.size(), ctx_);
      if (CVodeGetEstLocalErrors(mem_, ele.get()) == 0 && CVodeGetErrWeights(mem_, w.get()) == 0)
        failure_.suspect = largest_weighted_error(ele.get(), w.get());
      return false;
    }
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }
  const double* energy() const override { return m_.has_energy_witness() ? energy_.data() : nullptr; }

  SolverStats stats() const override {
    SolverStats st;
    st.warnings = sink_.warnings;
    st.first_warning = sink_.first_warning;
    if (!mem_) return st;
    CVodeGetNumSteps(mem_, &st.steps);
    CVodeGetNumRhsEvals(mem_, &st.rhs_evals);
    CVodeGetNumLinRhsEvals(mem_, &st.fd_jac_evals);
    CVodeGetNumJacEvals(mem_, &st.jac_evals);
    CVodeGetNumNonlinSolvIters(mem_, &st.nonlin_iters);
    CVodeGetNumNonlinSolvConvFails(mem_, &st.nonlin_conv_fails);
    CVodeGetNumErrTestFails(mem_, &st.err_test_fails);
    CVodeGetLastStep(mem_, &st.last_step);
    add_counts(st, before_restart_);  // CVodeReInit (at events, after dopri5) zeroes CVODE's counters
    if (across_) add_counts(st, across_->stats());
    return st;
  }
  const SolverFailure& failure() const override { return failure_; }
  std::vector<std::size_t> floored_unknowns() const override { return data_.weights.floored(); }
  std::vector<std::pair<double, double>> steps_across() const override {
    std::vector<std::pair<double, double>> spans = crossed_;
    if (across_) spans.emplace_back(across_from_, t_);  // (the run ended inside one)
    return spans;
  }

 private:
  /// CVODE restarted at (t_, y_) (after an event, or from dopri5), its
  /// counters kept.
  void restart() {
    SolverStats counted = stats();
    check_setup(CVodeReInit(mem_, t_, y_.get()), "CVodeReInit", sink_);
    if (m_.has_energy_witness()) check_setup(CVodeQuadReInit(mem_, energy_.get()), "CVodeQuadReInit", sink_);
    check_setup(CVodeSetStopTime(mem_, s_.t_end_s), "CVodeSetStopTime", sink_);  // (ReInit clears it)
    before_restart_ = counted;
  }

  /// At a change point ahead: dopri5 takes over from (t_, y_).
  void hand_over() {
    across_ = make_dopri5(m_, s_);
    across_->init(t_, y_.data(), nullptr);
    across_from_ = t_;
    across_energy_[0] = energy_.data()[0], across_energy_[1] = energy_.data()[1];
    last_independence_ = cut_joint_independence(m_, t_, y_.data(), data_.scratch);
    target_independence_ =
        std::min(kBeyond * std::max(last_independence_, kSmallestIndependence), kHighestTarget * start_independence_);
  }

  /// dopri5 on to t_out, in steps of kProbe, until the cut joints are
  /// target_independence_ beyond the crossing: CVODE restarts there (and
  /// across_ is empty). False, with failure_ set, if dopri5 fails.
  bool carry_across(double t_out) {
    for (;;) {
      const double t_next = std::min(t_out, across_->t() + kProbe);
      if (!across_->advance_to(t_next)) {
        failure_ = across_->failure();
        return false;
      }
      t_ = across_->t();
      std::copy(across_->y(), across_->y() + m_.size(), y_.data());
      if (const double* e = across_->energy())
        energy_.data()[0] = across_energy_[0] + e[0], energy_.data()[1] = across_energy_[1] + e[1];
      const double now = cut_joint_independence(m_, t_, y_.data(), data_.scratch);
      const bool beyond = now > last_independence_ && now >= target_independence_;
      last_independence_ = now;
      if (beyond) {
        crossed_.emplace_back(across_from_, t_);
        const SolverStats carried = across_->stats();
        across_.reset();
        restart();
        add_counts(before_restart_, carried);
        return true;
      }
      if (reached(t_, t_out)) return true;
    }
  }

  /// CVode to t_out (or a root before it), and the witness's integrals there.
  int solve(double t_out) {
    const int flag = CVode(mem_, t_out, y_.get(), &t_, CV_NORMAL);
    if (flag >= 0 && m_.has_energy_witness()) {
      double t_quad = t_;
      CVodeGetQuad(mem_, &t_quad, energy_.get());
    }
    return flag;
  }

  GuardedModel& m_;
  CallbackData data_;  ///< the callbacks' user data: the model and the error weights
  Settings s_;
  SunContext ctx_;
  SerialVector y_;
  SerialVector energy_;  ///< the energy witness's integrals (GuardedModel::has_energy_witness)
  MessageSink sink_;
  void* mem_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  double t_ = 0.0;
  SolverFailure failure_;
  std::vector<int> root_info_;  // per event: +1 rising, -1 falling, 0 no root (CVodeGetRootInfo)
  SolverStats before_restart_;  // counted before the latest restart (at an event or a step across)
  /// dopri5 takes over once the cut joints' independence falls to this share
  /// of the start's (as IDA steps across its lagrange rows' change points)
  /// and hands back where it is kBeyond times that beyond the crossing, but
  /// not above kHighestTarget of the start's, measured every kProbe (s).
  static constexpr double kWatchFrom = 0.1;
  static constexpr double kBeyond = 4.0;
  static constexpr double kHighestTarget = 0.9;
  static constexpr double kSmallestIndependence = 1e-3;
  static constexpr double kProbe = 2.5e-3;
  static constexpr std::size_t kListedCrossings = 4;  ///< in the summary
  double start_independence_ = 1.0;
  std::unique_ptr<Integrator> across_;  ///< dopri5, while it carries the run across a change point
  double across_from_ = 0.0;
  double across_energy_[2] = {0.0, 0.0};  ///< the witness's integrals where dopri5 took over
  double last_independence_ = 0.0, target_independence_ = 0.0;
  std::vector<std::pair<double, double>> crossed_;  ///< every span dopri5 carried: from, to
};

}  // namespace

std::unique_ptr<Integrator> make_cvode(GuardedModel& model, const Settings& s) {
  return std::make_unique<Cvode>(model, s);
}

}  // namespace mbgrt::detail
