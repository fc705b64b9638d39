// ida: variable-order BDF for F(t, y, y') = 0 with a dense direct linear
// solver. DAE models start from consistent values computed by IDACalcIC;
// ODE models run as r = y' - f(t, y), so IDA can be compared on any model.
#include <fmt/format.h>
#include <ida/ida.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <vector>

#include "solvers/sundials_util.hpp"

namespace mbgrt::detail {

namespace {

class Ida final : public Integrator {
 public:
  Ida(GuardedModel& model, const Settings& s)
      : m_(model), s_(s), y_(model.size(), ctx_), yp_(model.size(), ctx_), f_(model.size()) {}
  ~Ida() override {
    IDAFree(&mem_);
    if (ls_) SUNLinSolFree(ls_);
    if (A_) SUNMatDestroy(A_);
  }

  const char* name() const override { return "ida"; }
  std::string description() const override {
    return fmt::format(
        "IDA BDF, Newton, dense LU, finite-difference Jacobian{}, rtol {:g}, atol {:g}",
        m_.is_dae() ? "" : " (ODE as r = y' - f)", s_.rtol, s_.atol);
  }

  bool init(double t0, const double* y0, const double* yp0) override {
    const std::size_t n = m_.size();
    std::copy(y0, y0 + n, y_.data());
    t_ = t0;
    if (m_.is_dae()) {
      std::copy(yp0, yp0 + n, yp_.data());
    } else if (m_.derivative(t0, y_.data(), yp_.data()) != 0) {
      // For an ODE, y' = f(t0, y0) is already consistent; no IDACalcIC needed.
      failure_ = SolverFailure{t0, "IDA_FIRST_RES_FAIL", explain_flag("IDA_FIRST_RES_FAIL"), {}};
      return false;
    }

    mem_ = IDACreate(ctx_);
    check_setup(mem_, "IDACreate");
    check_setup(IDASetErrHandlerFn(mem_, MessageSink::handler, &sink_), "IDASetErrHandlerFn",
                sink_);
    check_setup(IDAInit(mem_, residual, t0, y_.get(), yp_.get()), "IDAInit", sink_);
    check_setup(IDASetUserData(mem_, this), "IDASetUserData", sink_);
    check_setup(IDASStolerances(mem_, s_.rtol, s_.atol), "IDASStolerances", sink_);
    check_setup(IDASetStopTime(mem_, s_.t_end_s), "IDASetStopTime", sink_);
    check_setup(IDASetMaxNumSteps(mem_, kMaxStepsPerOutput), "IDASetMaxNumSteps", sink_);
    // Like ACSL's MAXTERVAL: never step over more than one communication
    // interval, so an input that is zero at the start (a bump, a late step)
    // cannot be jumped over by an ever-growing step.
    check_setup(IDASetMaxStep(mem_, s_.interval_s), "IDASetMaxStep", sink_);
    const auto sn = static_cast<sunindextype>(n);
    A_ = SUNDenseMatrix(sn, sn, ctx_);
    check_setup(A_, "SUNDenseMatrix");
    ls_ = SUNLinSol_Dense(y_.get(), A_, ctx_);
    check_setup(ls_, "SUNLinSol_Dense");
    check_setup(IDASetLinearSolver(mem_, ls_, A_), "IDASetLinearSolver", sink_);

    if (m_.is_dae()) return consistent_initial_values(t0);
    return true;
  }

  bool advance_to(double t_out) override {
    int flag = IDASolve(mem_, t_out, &t_, y_.get(), yp_.get(), IDA_NORMAL);
    if (flag < 0) return fail(flag);
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }
  const double* yp() const override { return m_.is_dae() ? yp_.data() : nullptr; }

  SolverStats stats() const override {
    SolverStats st;
    st.warnings = sink_.warnings;
    st.first_warning = sink_.first_warning;
    if (!mem_) return st;
    IDAGetNumSteps(mem_, &st.steps);
    IDAGetNumResEvals(mem_, &st.rhs_evals);
    IDAGetNumLinResEvals(mem_, &st.fd_jac_evals);
    IDAGetNumJacEvals(mem_, &st.jac_evals);
    IDAGetNumNonlinSolvIters(mem_, &st.nonlin_iters);
    IDAGetNumNonlinSolvConvFails(mem_, &st.nonlin_conv_fails);
    IDAGetNumErrTestFails(mem_, &st.err_test_fails);
    IDAGetLastStep(mem_, &st.last_step);
    return st;
  }
  const SolverFailure& failure() const override { return failure_; }

 private:
  static int residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* user_data) {
    auto* self = static_cast<Ida*>(user_data);
    const double* yv = N_VGetArrayPointer(y);
    const double* ypv = N_VGetArrayPointer(yp);
    double* rv = N_VGetArrayPointer(r);
    if (self->m_.is_dae()) return self->m_.residual(t, yv, ypv, rv);
    double* f = self->f_.data();
    if (int flag = self->m_.derivative(t, yv, f); flag != 0) return flag;
    for (std::size_t i = 0; i < self->f_.size(); ++i) rv[i] = ypv[i] - f[i];
    return 0;
  }

  bool consistent_initial_values(double t0) {
    check_setup(IDASetId(mem_, id_vector().get()), "IDASetId", sink_);
    // Algebraic unknowns of an index-1 DAE are determined by the residual, not
    // integrated: keep them out of the local error test. Otherwise their
    // first-step derivative (unknown, guessed 0) forces tiny steps.
    check_setup(IDASetSuppressAlg(mem_, SUNTRUE), "IDASetSuppressAlg", sink_);
    // IDACalcIC only uses tout1 for direction and scale (it does not step
    // there), so one interval ahead is right even for a zero-length run.
    const double tout1 = t0 + s_.interval_s;
    if (int flag = IDACalcIC(mem_, IDA_YA_YDP_INIT, tout1); flag < 0) return fail(flag);
    check_setup(IDAGetConsistentIC(mem_, y_.get(), yp_.get()), "IDAGetConsistentIC", sink_);
    return true;
  }

  const SerialVector& id_vector() {
    id_ = std::make_unique<SerialVector>(m_.size(), ctx_);
    const auto& ids = m_.differential_ids();
    std::copy(ids.begin(), ids.end(), id_->data());
    return *id_;
  }

  bool fail(int flag) {
    double t_now = t_;
    IDAGetCurrentTime(mem_, &t_now);
    failure_ = make_failure(t_now, IDAGetReturnFlagName(flag), sink_);
    SerialVector ele(m_.size(), ctx_), w(m_.size(), ctx_);
    if (IDAGetEstLocalErrors(mem_, ele.get()) == 0 && IDAGetErrWeights(mem_, w.get()) == 0)
      failure_.suspect = largest_weighted_error(ele.get(), w.get());
    return false;
  }

  GuardedModel& m_;
  Settings s_;
  SunContext ctx_;
  SerialVector y_, yp_;
  std::unique_ptr<SerialVector> id_;
  std::vector<double> f_;  // scratch for f(t, y) when an ODE runs under IDA
  MessageSink sink_;
  void* mem_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  double t_ = 0.0;
  SolverFailure failure_;
};

}  // namespace

std::unique_ptr<Integrator> make_ida(GuardedModel& model, const Settings& s) {
  return std::make_unique<Ida>(model, s);
}

}  // namespace mbgrt::detail
