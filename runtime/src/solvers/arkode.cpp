// dopri5: ARKODE's explicit stepper with the Dormand–Prince 5(4) table —
// the adaptive non-stiff workhorse, comparable with MATLAB's ode45.
//
// ERKStep has no quadratures: the energy witness's two integrals ride after
// the model's unknowns, their rates the model's power at each stage, and the
// error weights keep them out of the step control (error_weights_with_witness).
#include <arkode/arkode_erkstep.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/sundials_util.hpp"

namespace mbgrt::detail {

namespace {

/// The energy witness's two integrals after the model's n unknowns (GuardedModel::has_energy_witness).
std::size_t witnesses(const GuardedModel& m) { return m.has_energy_witness() ? 2 : 0; }

/// ERKStep's right-hand side: the derivative, then the energy witness's rates.
int erk_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
  auto* m = static_cast<CallbackData*>(user_data)->model;
  const double* yv = N_VGetArrayPointer(y);
  double* ydotv = N_VGetArrayPointer(ydot);
  return m->derivative(t, yv, ydotv, GuardedModel::InputCheck::before, witnesses(*m) ? ydotv + m->size() : nullptr);
}

/// The model's weights (error_weights.hpp), and none for the witness's
/// integrals: ARKODE's norm is the RMS over all n + 2 entries, so the
/// model's are scaled by sqrt((n + 2) / n) to keep each step's error test
/// what it is without the witness.
int error_weights_with_witness(N_Vector y, N_Vector w, void* user_data) {
  const auto* data = static_cast<const CallbackData*>(user_data);
  double* wv = N_VGetArrayPointer(w);
  if (!data->weights(N_VGetArrayPointer(y), wv)) return -1;
  const std::size_t n = data->model->size(), q = witnesses(*data->model);
  const double scale = std::sqrt(static_cast<double>(n + q) / static_cast<double>(n));
  for (std::size_t i = 0; i < n; ++i) wv[i] *= scale;
  std::fill(wv + n, wv + n + q, 0.0);
  return 0;
}

class Dopri5 final : public Integrator {
 public:
  Dopri5(GuardedModel& model, const Settings& s)
      : m_(model), s_(s), n_(model.size()), y_(n_ + witnesses(model), ctx_) {}
  ~Dopri5() override { ERKStepFree(&mem_); }

  const char* name() const override { return "dopri5"; }
  std::string description() const override {
    return fmt::format("ARKODE ERKStep, Dormand-Prince 5(4), adaptive, rtol {:g}, atol {:g}",
                       s_.rtol, s_.atol);
  }

  bool init(double t0, const double* y0, const double*) override {
    std::copy(y0, y0 + n_, y_.data());
    std::fill(y_.data() + n_, y_.data() + n_ + witnesses(m_), 0.0);
    t_ = t0;
    remember();
    mem_ = ERKStepCreate(erk_rhs, t0, y_.get(), ctx_);
    check_setup(mem_, "ERKStepCreate");
    check_setup(ERKStepSetErrHandlerFn(mem_, MessageSink::handler, &sink_),
                "ERKStepSetErrHandlerFn", sink_);
    data_ = CallbackData{&m_, ErrorWeights(m_.model(), s_.rtol, s_.atol), nullptr};
    check_setup(ERKStepSetUserData(mem_, &data_), "ERKStepSetUserData", sink_);
    check_setup(ERKStepSetTableNum(mem_, ARKODE_DORMAND_PRINCE_7_4_5), "ERKStepSetTableNum", sink_);
    check_setup(ERKStepWFtolerances(mem_, witnesses(m_) ? error_weights_with_witness : error_weights),
                "ERKStepWFtolerances", sink_);
    check_setup(ERKStepSetStopTime(mem_, s_.t_end_s), "ERKStepSetStopTime", sink_);
    check_setup(ERKStepSetMaxNumSteps(mem_, kMaxStepsPerOutput), "ERKStepSetMaxNumSteps", sink_);
    // Like ACSL's MAXTERVAL: never step over more than one communication
    // interval, so an input that is zero at the start (a bump, a late step)
    // cannot be jumped over by an ever-growing step.
    check_setup(ERKStepSetMaxStep(mem_, s_.interval_s), "ERKStepSetMaxStep", sink_);
    if (const std::size_t k = m_.events().count(); k > 0) {
      check_setup(ERKStepRootInit(mem_, static_cast<int>(k), event_roots), "ERKStepRootInit", sink_);
      root_info_.assign(k, 0);
    }
    return true;
  }

  bool advance_to(double t_out) override {
    int flag = ERKStepEvolve(mem_, t_out, y_.get(), &t_, ARK_NORMAL);
    while (flag == ARK_ROOT_RETURN) {  // an event: switch its mode, restart there (counters kept)
      ERKStepGetRootInfo(mem_, root_info_.data());
      if (!fire_events(m_.events(), t_, y_.data(), root_info_, failure_)) return false;
      check_setup(ERKStepReset(mem_, t_, y_.get()), "ERKStepReset", sink_);
      if (reached(t_, t_out) || m_.events().pausing()) return true;  // the event is at the communication point, or pauses
      flag = ERKStepEvolve(mem_, t_out, y_.get(), &t_, ARK_NORMAL);
    }
    if (flag < 0) {
      // On failure ARKODE returns the last accepted y but the time of the
      // failed stage, and it offers no getter for the accepted step's time.
      // Fall back to the last communication point so (t, y) stay a true pair.
      t_ = t_good_;
      std::copy(y_good_.begin(), y_good_.end(), y_.data());
      failure_ = make_failure(t_, ERKStepGetReturnFlagName(flag), sink_);
      SerialVector ele(y_good_.size(), ctx_), w(y_good_.size(), ctx_);
      if (ERKStepGetEstLocalErrors(mem_, ele.get()) == 0 && ERKStepGetErrWeights(mem_, w.get()) == 0)
        failure_.suspect = largest_weighted_error(ele.get(), w.get());
      return false;
    }
    remember();
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }
  const double* energy() const override { return witnesses(m_) ? y_.data() + n_ : nullptr; }

  SolverStats stats() const override {
    SolverStats st;
    st.warnings = sink_.warnings;
    st.first_warning = sink_.first_warning;
    if (!mem_) return st;
    ERKStepGetNumSteps(mem_, &st.steps);
    ERKStepGetNumRhsEvals(mem_, &st.rhs_evals);
    ERKStepGetNumErrTestFails(mem_, &st.err_test_fails);
    ERKStepGetLastStep(mem_, &st.last_step);
    return st;
  }
  const SolverFailure& failure() const override { return failure_; }
  std::vector<std::size_t> floored_unknowns() const override { return data_.weights.floored(); }

 private:
  void remember() {
    t_good_ = t_;
    y_good_.assign(y_.data(), y_.data() + n_ + witnesses(m_));
  }

  GuardedModel& m_;
  CallbackData data_;  ///< the callbacks' user data: the model and the error weights
  Settings s_;
  std::size_t n_;  ///< the model's unknowns, the first of y_
  SunContext ctx_;
  SerialVector y_;
  MessageSink sink_;
  void* mem_ = nullptr;
  double t_ = 0.0;
  double t_good_ = 0.0;
  std::vector<double> y_good_;
  SolverFailure failure_;
  std::vector<int> root_info_;  // per event: +1 rising, -1 falling, 0 no root (ERKStepGetRootInfo)
};

}  // namespace

std::unique_ptr<Integrator> make_dopri5(GuardedModel& model, const Settings& s) {
  return std::make_unique<Dopri5>(model, s);
}

}  // namespace mbgrt::detail
