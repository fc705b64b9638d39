// Classic fixed-step fourth-order Runge–Kutta, written out by hand: it is the
// method for real-time loops, where a predictable cost per step matters more
// than error control, and it needs nothing from SUNDIALS.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "integrator.hpp"

namespace mbgrt::detail {

namespace {

class Rk4 final : public Integrator {
 public:
  Rk4(GuardedModel& model, const Settings& s)
      : m_(model),
        h_(s.step_s > 0.0 ? s.step_s : s.interval_s / 10.0),
        n_(model.size()),
        y_(n_),
        k1_(n_),
        k2_(n_),
        k3_(n_),
        k4_(n_),
        tmp_(n_) {}

  const char* name() const override { return "rk4"; }
  std::string description() const override {
    return fmt::format("classic Runge-Kutta 4, fixed step {:g} s", h_);
  }

  bool init(double t0, const double* y0, const double*) override {
    t_ = t0;
    std::copy(y0, y0 + n_, y_.begin());
    return true;
  }

  bool advance_to(double t_out) override {
    const double span = t_out - t_;
    if (span <= 0.0) return true;
    // Equal substeps, the last one forced onto t_out, so every communication
    // point is hit exactly and the step never exceeds the requested one.
    const auto count = static_cast<long long>(std::max(1.0, std::ceil(span / h_ - 1e-9)));
    const double h = span / static_cast<double>(count);
    for (long long i = 0; i < count; ++i) {
      const double t_next = (i + 1 == count) ? t_out : t_ + h;
      if (!step(t_next - t_)) return false;
      t_ = t_next;
    }
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }

  SolverStats stats() const override {
    SolverStats s;
    s.steps = steps_;
    s.rhs_evals = evals_;
    s.last_step = last_h_;
    return s;
  }
  const SolverFailure& failure() const override { return failure_; }

 private:
  bool step(double h) {
    if (!eval(t_, y_.data(), k1_.data())) return false;
    axpy(y_, h / 2, k1_);
    if (!eval(t_ + h / 2, tmp_.data(), k2_.data())) return false;
    axpy(y_, h / 2, k2_);
    if (!eval(t_ + h / 2, tmp_.data(), k3_.data())) return false;
    axpy(y_, h, k3_);
    if (!eval(t_ + h, tmp_.data(), k4_.data())) return false;
    for (std::size_t i = 0; i < n_; ++i)
      tmp_[i] = y_[i] + h / 6 * (k1_[i] + 2 * k2_[i] + 2 * k3_[i] + k4_[i]);
    // Keep the last finite state in y_ so terminal() and the report see it.
    if (!m_.check_state(t_ + h, tmp_.data())) return fail();
    y_.swap(tmp_);
    ++steps_;
    last_h_ = h;
    return true;
  }

  /// tmp = base + a * k
  void axpy(const std::vector<double>& base, double a, const std::vector<double>& k) {
    for (std::size_t i = 0; i < n_; ++i) tmp_[i] = base[i] + a * k[i];
  }

  bool eval(double t, const double* y, double* ydot) {
    ++evals_;
    // y is y_ (checked after the last step) plus finite multiples of
    // derivatives checked here: finite unless it overflowed, which the
    // derivative then shows and the guard blames on the state.
    if (m_.derivative(t, y, ydot, GuardedModel::InputCheck::on_failure) != 0) return fail();
    return true;
  }

  bool fail() {
    failure_.t = t_;  // the last state that was still finite
    failure_.flag_name = "RK4_NONFINITE";
    failure_.explanation =
        "a derivative or state became non-finite; a fixed-step method has no error control, "
        "so a step that is too large for the dynamics can blow up";
    return false;
  }

  GuardedModel& m_;
  double h_;
  std::size_t n_;
  double t_ = 0.0;
  std::vector<double> y_, k1_, k2_, k3_, k4_, tmp_;
  long steps_ = 0;
  long evals_ = 0;
  double last_h_ = 0.0;
  SolverFailure failure_;
};

}  // namespace

std::unique_ptr<Integrator> make_rk4(GuardedModel& model, const Settings& s) {
  return std::make_unique<Rk4>(model, s);
}

}  // namespace mbgrt::detail
