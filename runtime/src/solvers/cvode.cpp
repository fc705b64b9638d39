// cvode: variable-order BDF with Newton iterations and a dense direct linear
// solver — the default for stiff mechanical models. The Jacobian comes from
// the generated model when it has one (exact, and no extra RHS calls),
// otherwise from CVODE's finite differences. CVODES (CVODE with
// quadratures) carries the energy witness's integrals beside the state,
// outside Newton's iteration and the error test.
//
// In joint coordinates it leaves the change points of the cut joints to
// dopri5 (solvers/carry_across.hpp), where its corrector could land on the
// other branch of motion.
#include <cvodes/cvodes.h>
#include <fmt/format.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "solvers/carry_across.hpp"
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

/// The events' roots, then (if watched) the cut joints' independence
/// falling through the watch's level: a change point ahead.
int roots(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) {
  auto* data = static_cast<CallbackData*>(user_data);
  GuardedModel& m = *data->model;
  const std::size_t k = m.events().count();
  if (k > 0 && !m.events().functions(t, N_VGetArrayPointer(y), nullptr, g)) return -1;
  if (data->carry && data->carry->active()) g[k] = data->carry->root(t, N_VGetArrayPointer(y));
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
    const std::string across = carry_ ? carry_->describe(t_) : std::string();
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
    data_ = CallbackData{&m_, ErrorWeights(m_.model(), s_.rtol, s_.atol), nullptr};
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
    carry_.emplace(m_, s_, t0, y0);
    data_.carry = &*carry_;
    if (const std::size_t k = m_.events().count() + (carry_->active() ? 1 : 0); k > 0) {
      check_setup(CVodeRootInit(mem_, static_cast<int>(k), roots), "CVodeRootInit", sink_);
      root_info_.assign(k, 0);
      if (carry_->active()) {
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
    if (carry_->carrying()) {  // dopri5 carrying the run across a change point
      if (!carry_on(t_out)) return false;
      if (carry_->carrying() || reached(t_, t_out)) return true;
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
        if (m_.events().pausing()) return true;
      } else if (carry_->active() && root_info_[k] != 0) {  // a change point ahead
        carry_->begin(t_, y_.data(), energy_.data());
        if (!carry_on(t_out)) return false;
        if (carry_->carrying()) return true;
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
    if (carry_) carry_->add_open_counts(st);
    return st;
  }
  const SolverFailure& failure() const override { return failure_; }
  std::vector<std::size_t> floored_unknowns() const override { return data_.weights.floored(); }
  std::vector<std::pair<double, double>> steps_across() const override {
    return carry_ ? carry_->spans(t_) : std::vector<std::pair<double, double>>{};
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

  /// dopri5 carrying the run on to t_out; CVODE restarts where it ends.
  bool carry_on(double t_out) {
    SolverStats carried{0, 0, 0, 0, 0, 0, 0, 0.0, 0, {}};
    if (!carry_->carry(t_out, t_, y_.data(), energy_.data(), carried, failure_)) return false;
    if (!carry_->carrying()) {
      restart();
      add_counts(before_restart_, carried);
    }
    return true;
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
  std::optional<CarryAcross> carry_;  ///< the watch on the cut joints (set by init)
};

}  // namespace

std::unique_ptr<Integrator> make_cvode(GuardedModel& model, const Settings& s) {
  return std::make_unique<Cvode>(model, s);
}

}  // namespace mbgrt::detail
