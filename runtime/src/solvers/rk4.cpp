// Classic fixed-step fourth-order Runge–Kutta, written out by hand: it is the
// method for real-time loops, where a predictable cost per step matters more
// than error control, and it needs nothing from SUNDIALS. The energy
// witness's integrals take the same four stages, the model's power at each.
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
    energy_[0] = energy_[1] = 0.0;
    if (events_.count() > 0) {
      g_.resize(events_.count());
      g_new_.resize(events_.count());
      if (!events_.functions(t_, y_.data(), nullptr, g_.data())) return fail();
    }
    return true;
  }

  bool advance_to(double t_out) override {
    // Equal substeps, the last one forced onto t_out, so every communication
    // point is hit exactly and the step never exceeds the requested one; an
    // event cuts a step short, and the rest of the span is divided again.
    for (bool event = true; event;) {
      event = false;
      const double span = t_out - t_;
      if (span <= 0.0) return true;
      const auto count = static_cast<long long>(std::max(1.0, std::ceil(span / h_ - 1e-9)));
      const double h = span / static_cast<double>(count);
      for (long long i = 0; i < count && !event; ++i) {
        const double t_next = (i + 1 == count) ? t_out : t_ + h;
        if (!step(t_next - t_, t_next, event)) return false;
      }
    }
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }
  const double* energy() const override { return m_.has_energy_witness() ? energy_ : nullptr; }

  SolverStats stats() const override {
    SolverStats s;
    s.steps = steps_;
    s.rhs_evals = evals_;
    s.last_step = last_h_;
    return s;
  }
  const SolverFailure& failure() const override { return failure_; }

 private:
  /// One step of h from (t_, y_) to t_next (= t_ + h, exactly): y_ and t_
  /// move there, or to the first event inside it (`event` set).
  bool step(double h, double t_next, bool& event) {
    if (!trial(h)) return false;
    if (!events_.count()) return accept(t_next, h);
    if (!events_.functions(t_next, tmp_.data(), nullptr, g_new_.data())) return fail();
    double first = 2.0;  // fraction of h where the first crossing is, once located
    for (std::size_t k = 0; k < g_.size(); ++k)
      if ((g_[k] >= 0.0) != (g_new_[k] >= 0.0)) first = std::min(first, locate(k, h));
    if (first > 1.0) {
      g_.swap(g_new_);
      return accept(t_next, h);
    }
    // Every event whose function has crossed by then switches there (the
    // trial state and functions again: locate() left its last try in them).
    // (at least a few ulps past t_: a root at the step's start, where the
    // function sits at rounding level after a jump, must not stall the run)
    const double t_event = first == 1.0 ? t_next : std::max(t_ + first * h, std::nextafter(std::nextafter(t_, t_next), t_next));
    if (!trial(t_event - t_)) return false;
    if (!events_.functions(t_event, tmp_.data(), nullptr, g_new_.data())) return fail();
    const double t0 = t_;
    if (!accept(t_event, t_event - t0)) return false;
    events_.note_roots(t_);
    for (std::size_t k = 0; k < g_.size(); ++k)
      if ((g_[k] >= 0.0) != (g_new_[k] >= 0.0)) events_.fire(t_, k, g_new_[k] >= 0.0, y_.data());
    if (!m_.check_state(t_, y_.data())) return fail();  // (a jump may have changed it)
    if (!chatter_failure(events_, t_, failure_)) return false;
    event = true;
    return events_.functions(t_, y_.data(), nullptr, g_.data()) || fail();
  }

  /// The fraction of h at which event k's function crosses zero: Illinois
  /// (regula falsi) on steps of a fraction of h from (t_, y_), each an RK4
  /// step, to 1e-14 of the time. Returns the end of the bracket past the
  /// crossing, so that the function has changed sign there.
  double locate(std::size_t k, double h) {
    const bool before = g_[k] >= 0.0;
    double a = 0.0, fa = g_[k], b = 1.0, fb = g_new_[k];
    int side = 0;
    const double tol = 1e-14 * std::max(1.0, std::abs(t_)) / std::abs(h);
    for (int it = 0; it < 100 && b - a > tol; ++it) {
      double c = (fb != fa) ? b - fb * (b - a) / (fb - fa) : 0.5 * (a + b);
      if (!(c > a && c < b)) c = 0.5 * (a + b);
      if (!trial(c * h) || !events_.functions(t_ + c * h, tmp_.data(), nullptr, g_new_.data())) break;
      const double fc = g_new_[k];
      if ((fc >= 0.0) == before) {
        a = c, fa = fc;
        if (side == 1) fb /= 2;
        side = 1;
      } else {
        b = c, fb = fc;
        if (side == -1) fa /= 2;
        side = -1;
      }
    }
    return b;
  }

  /// tmp_ = the RK4 step of h from (t_, y_) (and energy_trial_ the witness's).
  bool trial(double h) {
    if (!eval(t_, y_.data(), k1_.data(), 0)) return false;
    axpy(y_, h / 2, k1_);
    if (!eval(t_ + h / 2, tmp_.data(), k2_.data(), 1)) return false;
    axpy(y_, h / 2, k2_);
    if (!eval(t_ + h / 2, tmp_.data(), k3_.data(), 2)) return false;
    axpy(y_, h, k3_);
    if (!eval(t_ + h, tmp_.data(), k4_.data(), 3)) return false;
    for (std::size_t i = 0; i < n_; ++i)
      tmp_[i] = y_[i] + h / 6 * (k1_[i] + 2 * k2_[i] + 2 * k3_[i] + k4_[i]);
    for (int k = 0; k < 2; ++k)
      energy_trial_[k] = energy_[k] + h / 6 * (power_[0][k] + 2 * power_[1][k] + 2 * power_[2][k] + power_[3][k]);
    return true;
  }

  /// The trial state becomes the state at t_next.
  bool accept(double t_next, double h) {
    // Keep the last finite state in y_ so terminal() and the report see it.
    if (!m_.check_state(t_next, tmp_.data())) return fail();
    y_.swap(tmp_);
    std::copy(energy_trial_, energy_trial_ + 2, energy_);
    t_ = t_next;
    ++steps_;
    last_h_ = h;
    return true;
  }


  /// tmp = base + a * k
  void axpy(const std::vector<double>& base, double a, const std::vector<double>& k) {
    for (std::size_t i = 0; i < n_; ++i) tmp_[i] = base[i] + a * k[i];
  }

  /// ydot at a stage (0 to 3), and the model's power there for the witness.
  bool eval(double t, const double* y, double* ydot, int stage) {
    ++evals_;
    // y is y_ (checked after the last step) plus finite multiples of
    // derivatives checked here: finite unless it overflowed, which the
    // derivative then shows and the guard blames on the state.
    if (m_.derivative(t, y, ydot, GuardedModel::InputCheck::on_failure) != 0) return fail();
    if (m_.has_energy_witness()) m_.power(t, y, nullptr, power_[stage]);
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
  Events& events_ = m_.events();
  std::vector<double> g_, g_new_;  // event functions at (t_, y_) and at the trial state
  double h_;
  std::size_t n_;
  double t_ = 0.0;
  std::vector<double> y_, k1_, k2_, k3_, k4_, tmp_;
  double power_[4][2] = {};      ///< the witness's rates at the four stages
  double energy_[2] = {};        ///< the witness's integrals at t_ (Integrator::energy)
  double energy_trial_[2] = {};  ///< ... at the trial state tmp_
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
