// solvers/fixed_step.hpp — what every fixed-step method shares, written once:
// equal substeps onto each output time, events located by re-taking the
// method's own step to a fraction of h (so a crossing is found at the
// method's order), the energy witness's integrals carried beside the state,
// a check of every accepted state, and the failure report. A method
// (explicit.cpp, linearly_implicit.cpp, generalized_alpha.cpp) only says how
// to take one step; the cost of a step is fixed, which is what real-time and
// hardware-in-the-loop runs need.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "integrator.hpp"

namespace mbgrt::detail {

/// The model as a method's stages see it: derivatives counted, and the
/// model's power for the energy witness.
class Stages {
 public:
  explicit Stages(GuardedModel& model) : m_(model) {}

  GuardedModel& model() { return m_; }
  std::size_t size() const { return m_.size(); }
  bool witness() const { return m_.has_energy_witness(); }

  /// ydot = f(t, y); false (with the guard's blame) if it is not finite.
  /// y is an accepted state plus finite multiples of checked derivatives or
  /// solutions of a linear system: finite unless it overflowed, which the
  /// derivative then shows and the guard blames on the state.
  /// With `rate`, the witness's rates there too, from the same evaluation.
  bool derivative(double t, const double* y, double* ydot, double* rate = nullptr) {
    ++evaluations_;
    return m_.derivative(t, y, ydot, GuardedModel::InputCheck::on_failure, rate) == 0;
  }
  /// ydot's position entries at (t, y) (GuardedModel::position_rates), the
  /// others left as they are; one derivative evaluation where the model has
  /// no position rates of its own.
  bool position_rates(double t, const double* y, double* ydot) {
    if (!m_.model().has_position_rates()) ++evaluations_;
    else ++position_evaluations_;
    return m_.position_rates(t, y, ydot) == 0;
  }
  /// rate[0..2): the power supplied and absorbed at (t, y), for the witness.
  void power(double t, const double* y, double* rate) { m_.power(t, y, nullptr, rate); }

  long evaluations() const { return evaluations_; }
  long position_evaluations() const { return position_evaluations_; }

 private:
  GuardedModel& m_;
  long evaluations_ = 0, position_evaluations_ = 0;
};

/// A failure's flag for the run report: "ROS2_SINGULAR" for ("ros2", "SINGULAR").
inline std::string failure_flag(const char* method, const char* what) {
  std::string flag = method;
  for (char& c : flag) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return flag + "_" + what;
}

/// Why a step failed other than by a value that became non-finite.
struct StepFailure {
  std::string flag;         ///< e.g. "ROS2_SINGULAR"
  std::string explanation;  ///< plain English, with what to try
};

/// A fixed-step integrator over `Method`, which provides:
///   Method(Stages&, const Settings&)
///   static constexpr const char* kName;      // as spelled on --solver
///   std::string description(double h) const;  // for the run summary
///   bool start(double t, const double* y);    // (re)start there: the run's start, after an event
///   bool trial(double t, const double* y, double h, double* y_out, double* energy_step);
///       // one step of h from (t, y) into y_out; energy_step[0..2) the
///       // witness's integrals over it (when Stages::witness())
///   void accept();                            // the last trial is the new state
///   const std::optional<StepFailure>& failure() const;  // why trial() failed, if not a non-finite value
///   void add_stats(SolverStats&) const;       // Jacobians, iterations
template <class Method>
class FixedStep final : public Integrator {
 public:
  FixedStep(GuardedModel& model, const Settings& s)
      : m_(model),
        stages_(model),
        method_(stages_, s),
        h_(s.step_s > 0.0 ? s.step_s : s.interval_s / 10.0),
        n_(model.size()),
        y_(n_),
        trial_(n_) {}

  const char* name() const override { return Method::kName; }
  std::string description() const override { return method_.description(h_); }

  bool init(double t0, const double* y0, const double*) override {
    t_ = t0;
    std::copy(y0, y0 + n_, y_.begin());
    energy_[0] = energy_[1] = 0.0;
    if (!method_.start(t_, y_.data())) return fail();
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
      if (event && events_.pausing()) return true;
    }
    return true;
  }

  double t() const override { return t_; }
  const double* y() const override { return y_.data(); }
  const double* energy() const override { return stages_.witness() ? energy_ : nullptr; }

  SolverStats stats() const override {
    SolverStats s;
    s.steps = steps_;
    s.rhs_evals = stages_.evaluations();
    s.last_step = last_h_;
    method_.add_stats(s);
    return s;
  }
  const SolverFailure& failure() const override { return failure_; }

 private:
  /// One step of h from (t_, y_) to t_next (= t_ + h, exactly): y_ and t_
  /// move there, or to the first event inside it (`event` set).
  bool step(double h, double t_next, bool& event) {
    if (!trial(h)) return false;
    if (!events_.count()) return accept(t_next, h);
    if (!events_.functions(t_next, trial_.data(), nullptr, g_new_.data())) return fail();
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
    const double t_event =
        first == 1.0 ? t_next : std::max(t_ + first * h, std::nextafter(std::nextafter(t_, t_next), t_next));
    if (!trial(t_event - t_)) return false;
    if (!events_.functions(t_event, trial_.data(), nullptr, g_new_.data())) return fail();
    const double t0 = t_;
    if (!accept(t_event, t_event - t0)) return false;
    events_.note_roots(t_);
    for (std::size_t k = 0; k < g_.size(); ++k)
      if ((g_[k] >= 0.0) != (g_new_[k] >= 0.0)) events_.fire(t_, k, g_new_[k] >= 0.0, y_.data());
    if (!m_.check_state(t_, y_.data())) return fail();  // (a jump may have changed it)
    if (!chatter_failure(events_, t_, failure_)) return false;
    event = true;
    // (the modes, and perhaps the state, changed: the method starts afresh)
    if (!method_.start(t_, y_.data())) return fail();
    return events_.functions(t_, y_.data(), nullptr, g_.data()) || fail();
  }

  /// The fraction of h at which event k's function crosses zero: Illinois
  /// (regula falsi) on steps of a fraction of h from (t_, y_), each the
  /// method's own step, to 1e-14 of the time. Returns the end of the bracket
  /// past the crossing, so that the function has changed sign there.
  double locate(std::size_t k, double h) {
    const bool before = g_[k] >= 0.0;
    double a = 0.0, fa = g_[k], b = 1.0, fb = g_new_[k];
    int side = 0;
    const double tol = 1e-14 * std::max(1.0, std::abs(t_)) / std::abs(h);
    for (int it = 0; it < 100 && b - a > tol; ++it) {
      double c = (fb != fa) ? b - fb * (b - a) / (fb - fa) : 0.5 * (a + b);
      if (!(c > a && c < b)) c = 0.5 * (a + b);
      if (!trial(c * h) || !events_.functions(t_ + c * h, trial_.data(), nullptr, g_new_.data())) break;
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

  /// trial_ = the method's step of h from (t_, y_), energy_trial_ the witness's integrals there.
  bool trial(double h) {
    double step_energy[2] = {0.0, 0.0};
    if (!method_.trial(t_, y_.data(), h, trial_.data(), step_energy)) return fail();
    for (int k = 0; k < 2; ++k) energy_trial_[k] = energy_[k] + step_energy[k];
    return true;
  }

  /// The trial state becomes the state at t_next.
  bool accept(double t_next, double h) {
    // Keep the last finite state in y_ so terminal() and the report see it.
    if (!m_.check_state(t_next, trial_.data())) return fail();
    y_.swap(trial_);
    method_.accept();
    std::copy(energy_trial_, energy_trial_ + 2, energy_);
    t_ = t_next;
    ++steps_;
    last_h_ = h;
    return true;
  }

  bool fail() {
    failure_.t = t_;  // the last state that was still finite
    if (const std::optional<StepFailure>& f = method_.failure()) {
      failure_.flag_name = f->flag;
      failure_.explanation = f->explanation;
      return false;
    }
    failure_.flag_name = failure_flag(Method::kName, "NONFINITE");
    failure_.explanation =
        "a derivative or state became non-finite; a fixed-step method has no error control, "
        "so a step that is too large for the dynamics can blow up";
    return false;
  }

  GuardedModel& m_;
  Stages stages_;
  Method method_;
  Events& events_ = m_.events();
  std::vector<double> g_, g_new_;  // event functions at (t_, y_) and at the trial state
  double h_;
  std::size_t n_;
  double t_ = 0.0;
  std::vector<double> y_, trial_;
  double energy_[2] = {};        ///< the witness's integrals at t_ (Integrator::energy)
  double energy_trial_[2] = {};  ///< ... at the trial state
  long steps_ = 0;
  double last_h_ = 0.0;
  SolverFailure failure_;
};

/// A fixed-step integrator of `Method` for `model`.
template <class Method>
std::unique_ptr<Integrator> make_fixed_step(GuardedModel& model, const Settings& s) {
  return std::make_unique<FixedStep<Method>>(model, s);
}

/// What an explicit method's failure() returns: never a reason of its own.
inline const std::optional<StepFailure>& no_step_failure() {
  static const std::optional<StepFailure> none;
  return none;
}

}  // namespace mbgrt::detail
