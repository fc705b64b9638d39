// ida: variable-order BDF for F(t, y, y') = 0 with a direct linear solver:
// dense LU, or KLU on the sparsity pattern the model gives (large DAEs; the
// Jacobian by finite differences over groups of columns, sparse_jacobian.hpp). DAE models start from consistent values computed by IDACalcIC,
// except DAEs with joint constraints (index-2 GGL form): their g and gdot rows
// depend on neither y' nor an algebraic unknown, which makes IDACalcIC's
// Newton matrix singular, so the runtime computes their y' and algebraic
// unknowns itself (constraints.cpp) and IDA starts from those. ODE models run
// as r = y' - f(t, y), so IDA can be compared on any model. IDAS (IDA with
// quadratures) carries the energy witness's integrals beside the unknowns,
// outside Newton's iteration and the error test.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <idas/idas.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "constraints.hpp"
#include "solvers/carry_across.hpp"
#include "solvers/change_point.hpp"
#include "solvers/sparse_jacobian.hpp"
#include "solvers/sparse_lu.hpp"
#include "solvers/sundials_util.hpp"

namespace mbgrt::detail {

namespace {

class Ida final : public Integrator {
 public:
  Ida(GuardedModel& model, const Settings& s)
      : m_(model), s_(s), y_(model.size(), ctx_), yp_(model.size(), ctx_), energy_(2, ctx_), f_(model.size()) {}
  ~Ida() override {
    IDAFree(&mem_);
    if (ls_) SUNLinSolFree(ls_);
    if (A_) SUNMatDestroy(A_);
  }

  const char* name() const override { return "ida"; }
  std::string description() const override {
    std::string note;
    if (!m_.is_dae())
      note = fmt::format(" (ODE as r = y' - f{})", carry_ ? carry_->describe(t_) : std::string());
    else if (m_.constraint_shape().any())
      note = fmt::format(
          " (index-2 constraints: algebraic unknowns outside the error test, their Newton "
          "weights scaled by h / interval; first step {}{}{}{}{})",
          h0_ > 0.0 ? fmt::format("{:.2g} s", h0_) : std::string("IDA's own"),
          relaxed_at_ ? fmt::format("; after a Newton failure at t = {:.9g} s, restarted with "
                                    "those weights scaled by h / 1 s",
                                    *relaxed_at_)
                      : std::string(),
          floored_at_ ? fmt::format("; after a failure at t = {:.9g} s, restarted with the absolute tolerances "
                                    "floored at rounding",
                                    *floored_at_)
                      : std::string(),
          describe_loosenings(),
          crossings_ > 0 ? fmt::format("; stepped across {} change point{} of the joints, where their rows became "
                                       "dependent (classical Runge-Kutta on the index-1 form, then assembled: "
                                       "solvers/change_point.hpp): {}",
                                       crossings_, crossings_ == 1 ? "" : "s", describe_crossings())
                         : std::string());
    const std::string linear =
        sparse_ ? fmt::format("sparse LU (KLU) on the model's pattern ({} of {} entries), finite-difference "
                              "Jacobian in {} column groups",
                              sparse_->nonzeros(), m_.size() * m_.size(), sparse_->groups())
                : std::string("dense LU, finite-difference Jacobian");
    return fmt::format("IDA BDF, Newton, {}{}, rtol {:g}, atol {:g}", linear, note, s_.rtol, s_.atol);
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
    weights_of_ = ErrorWeights(m_.model(), s_.rtol, s_.atol);
    check_setup(IDAWFtolerances(mem_, error_weights), "IDAWFtolerances", sink_);
    check_setup(IDASetStopTime(mem_, s_.t_end_s), "IDASetStopTime", sink_);
    check_setup(IDASetMaxNumSteps(mem_, kMaxStepsPerOutput), "IDASetMaxNumSteps", sink_);
    // Like ACSL's MAXTERVAL: never step over more than one communication
    // interval, so an input that is zero at the start (a bump, a late step)
    // cannot be jumped over by an ever-growing step.
    check_setup(IDASetMaxStep(mem_, s_.interval_s), "IDASetMaxStep", sink_);
    const auto sn = static_cast<sunindextype>(n);
    if (choose_sparse()) {
      A_ = SUNSparseMatrix(sn, sn, static_cast<sunindextype>(sparse_->nonzeros()), CSC_MAT, ctx_);
      check_setup(A_, "SUNSparseMatrix");
      ls_ = sparse_lu_factory()(y_.get(), A_, ctx_);  // KLU (solvers/klu.cpp)
      check_setup(ls_, "SUNLinSol_KLU");
      check_setup(IDASetLinearSolver(mem_, ls_, A_), "IDASetLinearSolver", sink_);
      check_setup(IDASetJacFn(mem_, sparse_jacobian), "IDASetJacFn", sink_);
    } else {
      A_ = SUNDenseMatrix(sn, sn, ctx_);
      check_setup(A_, "SUNDenseMatrix");
      ls_ = SUNLinSol_Dense(y_.get(), A_, ctx_);
      check_setup(ls_, "SUNLinSol_Dense");
      check_setup(IDASetLinearSolver(mem_, ls_, A_), "IDASetLinearSolver", sink_);
    }

    // The model's zero crossings, and a change point ahead: (a DAE with
    // lagrange rows) the rows' independence falling to a tenth of the
    // start's, or (an ODE) the cut joints' (solvers/carry_across.hpp).
    const detail::ConstraintShape& shape = m_.constraint_shape();
    watch_change_points_ = m_.is_dae() && shape.enforced &&
                           std::any_of(shape.lambda_at.begin(), shape.lambda_at.end(), [](long at) { return at >= 0; });
    if (!m_.is_dae()) carry_.emplace(m_, s_, t0, y0);
    const bool watched = watch_change_points_ || (carry_ && carry_->active());
    if (const std::size_t k = m_.events().count() + (watched ? 1 : 0); k > 0) {
      check_setup(IDARootInit(mem_, static_cast<int>(k), roots), "IDARootInit", sink_);
      root_info_.assign(k, 0);
      if (watched) {
        std::vector<int> direction(k, 0);
        direction.back() = -1;  // only as the rows become dependent
        check_setup(IDASetRootDirection(mem_, direction.data()), "IDASetRootDirection", sink_);
      }
    }
    std::fill(energy_.data(), energy_.data() + 2, 0.0);
    if (m_.has_energy_witness()) check_setup(IDAQuadInit(mem_, power, energy_.get()), "IDAQuadInit", sink_);
    if (m_.is_dae()) return consistent_initial_values(t0);
    return true;
  }

  bool advance_to(double t_out) override {
    // a point inside the last step across, or at its end (where IDA restarted)
    if (crossing_ && (t_out < crossing_->to() || reached(crossing_->to(), t_out))) return state_in_crossing(t_out);
    if (carry_ && carry_->carrying()) {  // dopri5 carrying the run across a change point
      if (!carry_on(t_out)) return false;
      if (carry_->carrying() || reached(t_, t_out)) return true;
    }
    int flag = solve(t_out);
    for (;;) {
      if (flag == IDA_ROOT_RETURN) {  // an event: switch its mode, restart there from consistent values
        IDAGetRootInfo(mem_, root_info_.data());
        const std::size_t k = m_.events().count();
        const std::vector<int> events(root_info_.begin(), root_info_.begin() + static_cast<long>(k));
        if (std::any_of(events.begin(), events.end(), [](int r) { return r != 0; })) {
          if (!fire_events(m_.events(), t_, y_.data(), events, failure_)) return false;
          if (!restart_after_event()) return false;
          if (m_.events().pausing()) return true;
        } else if (watch_change_points_ && root_info_[k] != 0 && step_across()) {  // a change point ahead
          if (t_out < crossing_->to()) return state_in_crossing(t_out);
        } else if (carry_ && carry_->active() && root_info_[k] != 0) {  // one of the cut joints
          carry_->begin(t_, y_.data(), energy_.data());
          if (!carry_on(t_out)) return false;
          if (carry_->carrying()) return true;
        }
        if (reached(t_, t_out)) return true;  // the event is at the communication point
        flag = solve(t_out);
        continue;
      }
      // A failure: a change point ahead, else weaker weights for the
      // multipliers, else the tolerances' floor (each of those once), else
      // looser tolerances; a root or a failure after any is handled as at
      // the first.
      const bool stuck = flag == IDA_CONV_FAIL || flag == IDA_TOO_MUCH_WORK;
      if (!stuck && flag != IDA_ERR_FAIL) break;
      if (step_across()) {
        if (t_out < crossing_->to()) return state_in_crossing(t_out);
        if (reached(t_, t_out)) return true;  // the steps across ended the run
      } else if (!(stuck && (relax_index_two() || floor_tolerances())) && !loosen_tolerances()) {
        break;
      }
      flag = solve(t_out);
    }
    if (flag < 0) return fail(flag);
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }
  const double* yp() const override { return m_.is_dae() ? yp_.data() : nullptr; }
  const double* energy() const override { return m_.has_energy_witness() ? energy_.data() : nullptr; }

  SolverStats stats() const override {
    SolverStats st;
    st.warnings = sink_.warnings;
    st.first_warning = sink_.first_warning;
    if (!mem_) return st;
    IDAGetNumSteps(mem_, &st.steps);
    IDAGetNumResEvals(mem_, &st.rhs_evals);
    IDAGetNumLinResEvals(mem_, &st.fd_jac_evals);  // IDA's own differences (dense)
    if (sparse_) st.fd_jac_evals += sparse_->evaluations();  // ours (sparse): not reset by a restart
    IDAGetNumJacEvals(mem_, &st.jac_evals);
    IDAGetNumNonlinSolvIters(mem_, &st.nonlin_iters);
    IDAGetNumNonlinSolvConvFails(mem_, &st.nonlin_conv_fails);
    IDAGetNumErrTestFails(mem_, &st.err_test_fails);
    IDAGetLastStep(mem_, &st.last_step);
    // IDAReInit (relax_index_two) zeroes IDA's counters: add what came before.
    add_counts(st, before_restart_);
    if (carry_) carry_->add_open_counts(st);
    return st;
  }
  const SolverFailure& failure() const override { return failure_; }
  std::vector<std::size_t> floored_unknowns() const override { return weights_of_.floored(); }
  std::vector<Loosening> loosenings() const override { return loosenings_; }
  std::vector<std::pair<double, double>> steps_across() const override {
    return carry_ ? carry_->spans(t_) : std::vector<std::pair<double, double>>{};
  }

 private:
  /// IDASolve to t_out (or a root before it), and the witness's integrals
  /// there (after a failure, at the last step IDA completed, where
  /// relax_index_two restarts).
  int solve(double t_out) {
    const int flag = IDASolve(mem_, t_out, &t_, y_.get(), yp_.get(), IDA_NORMAL);
    if (m_.has_energy_witness()) {
      double t_quad = t_;
      IDAGetQuad(mem_, &t_quad, energy_.get());
    }
    return flag;
  }
  /// IDAReInit at (t_, y_, yp_), the witness's integrals carried on.
  bool reinit() {
    if (IDAReInit(mem_, t_, y_.get(), yp_.get()) != IDA_SUCCESS) return false;
    return !m_.has_energy_witness() || IDAQuadReInit(mem_, energy_.get()) == IDA_SUCCESS;
  }
  /// The energy witness's rates (IDAS' quadrature right-hand side).
  static int power(sunrealtype t, N_Vector y, N_Vector yp, N_Vector rate, void* user_data) {
    auto* self = static_cast<Ida*>(user_data);
    const double* ypv = self->m_.is_dae() ? N_VGetArrayPointer(yp) : nullptr;
    return self->m_.power(t, N_VGetArrayPointer(y), ypv, N_VGetArrayPointer(rate));
  }

  static int roots(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype* g, void* user_data) {
    auto* self = static_cast<Ida*>(user_data);
    const double* ypv = self->m_.is_dae() ? N_VGetArrayPointer(yp) : nullptr;
    const std::size_t k = self->m_.events().count();
    if (k > 0 && !self->m_.events().functions(t, N_VGetArrayPointer(y), ypv, g)) return -1;
    if (self->carry_ && self->carry_->active()) g[k] = self->carry_->root(t, N_VGetArrayPointer(y));
    if (self->watch_change_points_)
      g[k] = self->start_independence_ > 0.0
                 ? detail::row_independence(self->m_.model(), self->m_.constraint_shape(), t, N_VGetArrayPointer(y)) -
                       kWatchFrom * self->start_independence_
                 : 1.0;
    return 0;
  }

  /// After an event: y' jumps with the switched mode. An ODE takes f(t, y);
  /// a DAE new consistent y' and algebraic unknowns (IDACalcIC, or the
  /// runtime's own solve for the index-2 form), then IDA restarts at order 1.
  bool restart_after_event() {
    const std::size_t n = m_.size();
    const bool index_two = m_.is_dae() && m_.constraint_shape().any();
    SolverStats counted = stats();
    if (sparse_) counted.fd_jac_evals -= sparse_->evaluations();  // counted on by stats() itself
    if (!m_.is_dae()) {
      if (m_.derivative(t_, y_.data(), yp_.data()) != 0) return fail_at_event("the derivative after the event is not finite");
    } else if (index_two) {
      std::vector<double> y(y_.data(), y_.data() + n), yp(yp_.data(), yp_.data() + n);
      const InitialValuesReport r = detail::consistent_initial_values(m_.model(), m_.constraint_shape(), t_, y.data(), yp.data());
      if (!r.ok) return fail_at_event("no consistent y' after the event: " + r.error);
      std::copy(y.begin(), y.end(), y_.data());
      std::copy(yp.begin(), yp.end(), yp_.data());
    }
    if (!reinit()) return fail_at_event("IDAReInit failed");
    before_restart_ = counted;
    IDASetStopTime(mem_, s_.t_end_s);  // (ReInit clears it)
    if (index_two) {  // a first step as at the start (setup_index_two)
      h0_ = initial_step(t_);
      if (h0_ > 0.0) IDASetInitStep(mem_, h0_);
    } else if (m_.is_dae()) {
      if (int flag = IDACalcIC(mem_, IDA_YA_YDP_INIT, t_ + s_.interval_s); flag < 0) return fail(flag);
      check_setup(IDAGetConsistentIC(mem_, y_.get(), yp_.get()), "IDAGetConsistentIC", sink_);
    }
    return true;
  }
  bool fail_at_event(const std::string& why) {
    failure_ = SolverFailure{t_, "IDA_EVENT_RESTART", "restarting after an event: " + why, {}, -1};
    return false;
  }

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

  /// KLU on the model's pattern: asked for, or a large DAE that gives one.
  bool choose_sparse() {
    if (!m_.is_dae() || s_.linear_solver == LinearSolver::dense) return false;
    if (s_.linear_solver == LinearSolver::automatic && m_.size() < kSparseFromUnknowns) return false;
    std::vector<long> starts, rows;
    if (!m_.model().residual_sparsity(starts, rows)) return false;
    if (!sparse_lu_factory()) {  // a program that did not call mbgrt::use_sparse_lu()
      if (s_.linear_solver == LinearSolver::automatic) return false;
      throw std::invalid_argument(
          "--linear-solver sparse: this program was built without the sparse solver (KLU); "
          "it calls mbgrt::use_sparse_lu() to have it (mbgrt/features.hpp)");
    }
    sparse_.emplace(std::move(starts), std::move(rows));
    if (sparse_->size() != m_.size()) throw std::invalid_argument("residual_sparsity: not one column per unknown");
    weights_ = std::make_unique<SerialVector>(m_.size(), ctx_);
    return true;
  }

  /// IDALsJacFn: J = dF/dy + c_j dF/dy' on the pattern, by grouped differences.
  static int sparse_jacobian(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix J,
                             void* user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) {
    auto* self = static_cast<Ida*>(user_data);
    SparseJacobian& sj = *self->sparse_;
    double h = 0.0;
    IDAGetCurrentStep(self->mem_, &h);
    if (IDAGetErrWeights(self->mem_, self->weights_->get()) != IDA_SUCCESS) return -1;
    // perturb copies: IDA's y and y' stay as they are
    N_VScale(1.0, y, tmp1);
    N_VScale(1.0, yp, tmp2);
    (void)tmp3;
    // SUNMatZero before this call cleared the structure too: write it again
    sunindextype* starts = SUNSparseMatrix_IndexPointers(J);
    sunindextype* rows = SUNSparseMatrix_IndexValues(J);
    for (std::size_t j = 0; j < sj.column_starts().size(); ++j) starts[j] = static_cast<sunindextype>(sj.column_starts()[j]);
    for (std::size_t k = 0; k < sj.rows().size(); ++k) rows[k] = static_cast<sunindextype>(sj.rows()[k]);
    const SparseJacobian::Residual residual = [&](const double* yv, const double* ypv, double* rv) {
      return self->m_.residual(t, yv, ypv, rv);
    };
    return sj.fill(residual, cj, h, N_VGetArrayPointer(tmp1), N_VGetArrayPointer(tmp2), N_VGetArrayPointer(r),
                   self->weights_->data(), SUNSparseMatrix_Data(J));
  }

  bool consistent_initial_values(double t0) {
    check_setup(IDASetId(mem_, id_vector().get()), "IDASetId", sink_);
    // Algebraic unknowns of an index-1 DAE are determined by the residual, not
    // integrated: keep them out of the local error test. Otherwise their
    // first-step derivative (unknown, guessed 0) forces tiny steps. For the
    // index-2 multipliers of a constrained DAE this is required, not just
    // helpful: their local error estimate does not shrink with the step.
    check_setup(IDASetSuppressAlg(mem_, SUNTRUE), "IDASetSuppressAlg", sink_);
    // Constrained DAE: y and y' are already consistent (run_main computed them).
    if (m_.constraint_shape().any()) return setup_index_two(t0);
    // IDACalcIC only uses tout1 for direction and scale (it does not step
    // there), so one interval ahead is right even for a zero-length run.
    const double tout1 = t0 + s_.interval_s;
    if (int flag = IDACalcIC(mem_, IDA_YA_YDP_INIT, tout1); flag < 0) return fail(flag);
    check_setup(IDAGetConsistentIC(mem_, y_.get(), yp_.get()), "IDAGetConsistentIC", sink_);
    return true;
  }

  /// Two settings the index-2 (GGL) form needs. Rounding noise in the
  /// constraint rows (eps times the size of their terms) reaches the
  /// multipliers amplified by 1/h, and at atol-sized weights that alone fails
  /// IDA's Newton convergence test once the step is small (below ~1e-5 s for
  /// a chain of rods at atol 1e-10; runs then died in a cascade of step cuts):
  ///  * the first step comes from the second derivative (BDF1's local error
  ///    h^2/2 |y''| at the tolerance) instead of IDA's |y'|-based guess,
  ///    which for a mechanism released from rest is around 1e-10 s;
  ///  * the error weights of the algebraic unknowns are scaled by
  ///    min(1, h / interval), the usual scaling of index-2 variables by the
  ///    step made dimensionless, so that small steps stay possible. The states
  ///    keep their weights, and the multipliers are outside the error test.
  ///    Rounding noise delta in the g rows moves mu by delta / h, which then
  ///    weighs delta / (interval atol) whatever the step (and IDA keeps a
  ///    step's weights through its retries, so cutting h only makes it
  ///    worse): at atol * interval near delta (1e-11 * 1e-4 s for Andrews'
  ///    squeezer) Newton never converges (IDA_CONV_FAIL), or the steps
  ///    collapse (IDA_TOO_MUCH_WORK). relax_index_two() then restarts with
  ///    the reference time 1 s instead of the interval. (Not from the start:
  ///    h / interval keeps the multipliers, and through them the states,
  ///    converged tighter, which the energy balance of the crank-rocker and
  ///    the drift of Andrews' squeezer at loose tolerances measurably need.)
  bool setup_index_two(double t0) {
    index_two_ = true;
    start_independence_ = detail::row_independence(m_.model(), m_.constraint_shape(), t0, y_.data());
    h0_ = initial_step(t0);
    if (h0_ > 0.0) check_setup(IDASetInitStep(mem_, h0_), "IDASetInitStep", sink_);
    return true;
  }

  static int error_weights(N_Vector y, N_Vector w, void* user_data) {
    auto* self = static_cast<Ida*>(user_data);
    double* wv = N_VGetArrayPointer(w);
    // (a false makes IDA report IDA_BAD_EWT, as with its own weights)
    if (!self->weights_of_(N_VGetArrayPointer(y), wv)) return -1;
    if (!self->index_two_) return 0;
    double h = 0.0;  // the step about to be attempted (0 before the first one)
    IDAGetCurrentStep(self->mem_, &h);
    if (!(h > 0.0)) h = self->h0_ > 0.0 ? self->h0_ : self->s_.interval_s;
    const std::vector<double>& ids = self->m_.differential_ids();
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (ids[i] == 0.0) wv[i] *= std::min(1.0, h / self->h_ref_);
    return 0;
  }

  /// sqrt(2 / |y''|) in IDA's weighted RMS norm over the states, halved, with
  /// y'' from consistent y' one thousandth of an interval ahead; 0 (IDA's
  /// own guess) if that cannot be computed.
  double initial_step(double t0) {
    const ConstraintShape& shape = m_.constraint_shape();
    const std::size_t n = shape.n, ns = shape.ns;
    if (ns == 0) return 0.0;
    const double delta = 1e-3 * s_.interval_s;
    std::vector<double> y1(y_.data(), y_.data() + n), yp1(yp_.data(), yp_.data() + n);
    for (std::size_t i = 0; i < ns; ++i) y1[i] += delta * yp_.data()[i];
    if (!detail::consistent_initial_values(m_.model(), shape, t0 + delta, y1.data(), yp1.data()).ok)
      return 0.0;
    std::vector<double> weights(n);
    if (!weights_of_(y_.data(), weights.data())) return 0.0;
    double sum = 0.0;
    for (std::size_t i = 0; i < ns; ++i) {
      const double w = weights[i];
      const double ypp = (yp1[i] - yp_.data()[i]) / delta;
      sum += ypp * w * ypp * w;
    }
    const double norm = std::sqrt(sum / static_cast<double>(ns));
    double h = s_.interval_s;
    if (norm > 0.0 && std::isfinite(norm)) h = std::min(h, 0.5 * std::sqrt(2.0 / norm));
    if (s_.t_end_s > t0) h = std::min(h, s_.t_end_s - t0);
    return h;
  }

  /// dopri5 carrying an ODE on to t_out; IDA restarts where it ends, with
  /// y' = f(t, y).
  bool carry_on(double t_out) {
    SolverStats carried{0, 0, 0, 0, 0, 0, 0, 0.0, 0, {}};
    if (!carry_->carry(t_out, t_, y_.data(), energy_.data(), carried, failure_)) return false;
    if (carry_->carrying()) return true;
    SolverStats counted = stats();
    if (sparse_) counted.fd_jac_evals -= sparse_->evaluations();  // counted on by stats() itself
    if (m_.derivative(t_, y_.data(), yp_.data()) != 0 || !reinit()) {
      failure_ = SolverFailure{t_, "IDA_CHANGE_POINT", "no restart after dopri5 carried the run across a change point "
                               "of the cut joints", {}, -1};
      return false;
    }
    before_restart_ = counted;
    add_counts(before_restart_, carried);
    IDASetStopTime(mem_, s_.t_end_s);  // (ReInit clears it)
    return true;
  }

  /// After IDA stopped near a change point of the joints (solvers/
  /// change_point.hpp): one Runge-Kutta step across it from the last point
  /// IDA completed, and IDA restarted beyond it. False (nothing changed) if
  /// the rows there are not close to dependent, or the step fails.
  bool step_across() {
    if (!index_two_ || crossings_ >= kMaxCrossings) return false;
    std::string why;
    auto step = detail::ChangePointStep::plan(m_.model(), m_.constraint_shape(), start_independence_, t_, y_.data(),
                                              yp_.data(), s_.t_end_s, why);
    if (!step) return false;
    double energy[2] = {energy_.data()[0], energy_.data()[1]};
    std::vector<double> y(m_.size()), yp(m_.size());
    if (!step->state_at(step->to(), y.data(), yp.data(), energy, why)) return false;
    SolverStats counted = stats();
    if (sparse_) counted.fd_jac_evals -= sparse_->evaluations();  // counted on by stats() itself
    crossing_ = std::move(step);
    crossing_energy_[0] = energy_.data()[0], crossing_energy_[1] = energy_.data()[1];
    t_ = crossing_->to();
    std::copy(y.begin(), y.end(), y_.data());
    std::copy(yp.begin(), yp.end(), yp_.data());
    std::copy(energy, energy + 2, energy_.data());
    if (!reinit()) return false;
    before_restart_ = counted;
    if (crossings_++ < kListedCrossings)
      crossing_list_.push_back({crossing_->from(), crossing_->to(), crossing_->row()});
    h0_ = initial_step(t_);
    if (h0_ > 0.0) IDASetInitStep(mem_, h0_);
    IDASetStopTime(mem_, s_.t_end_s);
    return true;
  }

  /// A communication point inside the last step across: that step, shorter.
  bool state_in_crossing(double t_out) {
    std::vector<double> y(m_.size()), yp(m_.size());
    double energy[2] = {crossing_energy_[0], crossing_energy_[1]};
    std::string why;
    if (!crossing_->state_at(t_out, y.data(), yp.data(), energy, why)) {
      failure_ = SolverFailure{t_out, "IDA_CHANGE_POINT", "stepping across a change point of the joints: " + why, {}, -1};
      return false;
    }
    t_ = t_out;
    std::copy(y.begin(), y.end(), y_.data());
    std::copy(yp.begin(), yp.end(), yp_.data());
    std::copy(energy, energy + 2, energy_.data());
    return true;
  }

  /// After IDA_CONV_FAIL or IDA_TOO_MUCH_WORK on an index-2 DAE: scale the
  /// multipliers' weights by h / 1 s (the RADAU5 scaling of index-2
  /// variables, under which their rounding noise weighs delta / atol, as in
  /// a state) instead of h / interval, and restart from the last step IDA
  /// completed, with y' and the multipliers made consistent there. Once per
  /// run; false (nothing changed) if not applicable.
  bool relax_index_two() {
    if (!m_.is_dae() || !m_.constraint_shape().any() || relaxed_at_) return false;
    if (s_.interval_s >= 1.0) return false;  // already the weaker scaling
    h_ref_ = 1.0;
    if (!restart_here()) return false;
    relaxed_at_ = t_;
    return true;
  }

  /// After IDA_CONV_FAIL or IDA_TOO_MUCH_WORK (and relax_index_two): the
  /// absolute tolerances get their rounding floor (ErrorWeights), and IDA
  /// restarts from the last step it completed. Once per run.
  bool floor_tolerances() {
    if (weights_of_.floor_engaged() || !m_.is_dae() || !m_.constraint_shape().any()) return false;
    weights_of_.engage_floor();
    if (!restart_here()) return false;
    floored_at_ = t_;
    return true;
  }

  /// After a failure that nothing above cured, at an rtol tighter than
  /// ErrorWeights::kResolvedRtol (4.5e6 unit roundoffs; a failure at a
  /// looser one is the model's, and is reported as it is): every tolerance
  /// ten times looser from IDA's last step on.
  /// At such tolerances the failure is the arithmetic's, not the model's:
  /// the rows' rounding noise, amplified as they lose independence, passes
  /// the tolerance before the change point's watch fires (N four-bars with
  /// multipliers at rtol 1e-12: the Newton iteration failed at steps down to
  /// 1e-12 s, 0.05 s before the first aligned passage, with the tolerances
  /// floored; rtol 1e-11 ran through). DASSL answers a tolerance too small
  /// for the machine the same way (IDID = -2). For the rest of the run: going
  /// back to the asked ones after the passage failed again just beyond it,
  /// and the restarts cost more accuracy than the looser tolerance (N = 4 at
  /// rtol 1e-12 over 1 s: 1.5e-8 m, against 1.4e-9 m). Repeatable up to
  /// kResolvedRtol; false (nothing changed) beyond it.
  bool loosen_tolerances() {
    const double scale = weights_of_.scale() * kLoosen;
    if (!m_.is_dae() || s_.rtol * scale > ErrorWeights::kResolvedRtol * (1.0 + 1e-9)) return false;
    weights_of_.loosen(kLoosen);
    if (!restart_here()) return false;
    loosenings_.push_back({t_, s_.rtol * scale, s_.atol * scale});
    return true;
  }

  static constexpr double kLoosen = 10.0;

  /// An order-1 restart of an index-2 DAE from IDA's last step. IDA's y'
  /// there is the BDF formula's, not the DAE's: the restart needs the
  /// consistent one (as at the start).
  bool restart_here() {
    std::vector<double> y(y_.data(), y_.data() + m_.size()), yp(yp_.data(), yp_.data() + m_.size());
    if (!detail::consistent_initial_values(m_.model(), m_.constraint_shape(), t_, y.data(),
                                           yp.data())
             .ok)
      return false;
    std::copy(y.begin(), y.end(), y_.data());
    std::copy(yp.begin(), yp.end(), yp_.data());
    SolverStats counted = stats();
    if (sparse_) counted.fd_jac_evals -= sparse_->evaluations();  // counted on by stats() itself
    if (!reinit()) return false;
    before_restart_ = counted;
    h0_ = initial_step(t_);
    if (h0_ > 0.0) IDASetInitStep(mem_, h0_);
    IDASetStopTime(mem_, s_.t_end_s);
    return true;
  }

  const SerialVector& id_vector() {
    if (!id_) {
      id_ = std::make_unique<SerialVector>(m_.size(), ctx_);
      const auto& ids = m_.differential_ids();
      std::copy(ids.begin(), ids.end(), id_->data());
    }
    return *id_;
  }

  bool fail(int flag) {
    double t_now = t_;
    IDAGetCurrentTime(mem_, &t_now);
    failure_ = make_failure(t_now, IDAGetReturnFlagName(flag), sink_);
    SerialVector ele(m_.size(), ctx_), w(m_.size(), ctx_);
    if (IDAGetEstLocalErrors(mem_, ele.get()) == 0 && IDAGetErrWeights(mem_, w.get()) == 0) {
      // The algebraic unknowns of a DAE are outside the error test
      // (IDASetSuppressAlg): their estimates did not limit the step, so they
      // must not be named as the state that forced it down.
      if (m_.is_dae()) N_VProd(w.get(), id_vector().get(), w.get());
      failure_.suspect = largest_weighted_error(ele.get(), w.get());
    }
    return false;
  }

  GuardedModel& m_;
  Settings s_;
  SunContext ctx_;
  SerialVector y_, yp_;
  SerialVector energy_;  ///< the energy witness's integrals (GuardedModel::has_energy_witness)
  std::unique_ptr<SerialVector> id_;
  std::vector<double> f_;  // scratch for f(t, y) when an ODE runs under IDA
  MessageSink sink_;
  void* mem_ = nullptr;
  std::optional<SparseJacobian> sparse_;      ///< the pattern and its column groups, with KLU
  std::unique_ptr<SerialVector> weights_;     ///< IDA's error weights, read for the increments
  SUNMatrix A_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  double t_ = 0.0;
  double h0_ = 0.0;  ///< first step chosen for an index-2 DAE (0: IDA's own)
  ErrorWeights weights_of_;  ///< per unknown, by its nominal size and its vector (error_weights.hpp)
  bool index_two_ = false;   ///< an index-2 DAE: the algebraic unknowns' weights scaled by the step
  double h_ref_ = s_.interval_s;  ///< multipliers' weights scaled by min(1, h / h_ref_)
  std::optional<double> relaxed_at_;  ///< time of the restart by relax_index_two()
  std::optional<double> floored_at_;  ///< time of the restart by floor_tolerances()
  std::vector<Loosening> loosenings_;  ///< the restarts by loosen_tolerances()
  double start_independence_ = 0.0;  ///< of the joints' rows at the start (detail::row_independence)
  std::optional<detail::ChangePointStep> crossing_;  ///< the last step across a change point
  std::optional<detail::CarryAcross> carry_;  ///< an ODE's watch on its cut joints (set by init)
  double crossing_energy_[2] = {0.0, 0.0};           ///< the witness's integrals where it began
  int crossings_ = 0;
  /// The first kListedCrossings steps across: where each began and ended,
  /// and the position row least independent where it began.
  struct Crossing {
    double from, to;
    std::size_t row;
  };
  std::vector<Crossing> crossing_list_;
  static constexpr int kListedCrossings = 4;
  std::string describe_loosenings() const {
    std::string out;
    for (const Loosening& l : loosenings_)
      out += fmt::format("; after a failure at t = {:.9g} s, went on at rtol {:g}, atol {:g}", l.t_s, l.rtol, l.atol);
    return out;
  }
  std::string describe_crossings() const {
    std::vector<std::string> parts;
    for (const Crossing& c : crossing_list_)
      parts.push_back(fmt::format("t = {:.6g} to {:.6g} s ('{}' the least independent row)", c.from, c.to,
                                  detail::joint_row_name(m_.model(), c.row)));
    if (crossings_ > kListedCrossings) parts.push_back(fmt::format("and {} more", crossings_ - kListedCrossings));
    return fmt::format("{}", fmt::join(parts, ", "));
  }
  static constexpr int kMaxCrossings = 100000;
  /// IDA steps across a change point once the rows' independence falls to
  /// this share of the start's (measured on IFToMM's N four-bar: at 1e-8 IDA
  /// otherwise came within 1e-3 of the crossing, or stepped through it, and
  /// either changed the energy by about 3e-5 J).
  static constexpr double kWatchFrom = 0.1;
  bool watch_change_points_ = false;  ///< a root function on the rows' independence (DAE with lagrange rows)
  /// IDA's counters up to the restart (zero until then).
  SolverStats before_restart_{0, 0, 0, 0, 0, 0, 0, 0.0, 0, {}};
  std::vector<int> root_info_;  // per event: +1 rising, -1 falling, 0 no root (IDAGetRootInfo)
  SolverFailure failure_;
};

}  // namespace

std::unique_ptr<Integrator> make_ida(GuardedModel& model, const Settings& s) {
  return std::make_unique<Ida>(model, s);
}

}  // namespace mbgrt::detail
