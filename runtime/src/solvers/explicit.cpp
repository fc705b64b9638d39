// The explicit fixed-step methods, one derivative per stage: explicit Euler
// and Heun (ACSL's fixed-step staples, orders 1 and 2), the classic
// Runge-Kutta 4, and the semi-implicit (symplectic) Euler of mechanical
// models. None needs SUNDIALS; fixed_step.hpp does the rest (events, the
// witness, the checks). The witness integrates the model's power with the
// method's own quadrature: its stages' powers with its weights.
#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "fixed_step.hpp"

namespace mbgrt::detail {

namespace {

/// Shared by the explicit methods: nothing to start, accept or report.
class Explicit {
 public:
  Explicit(Stages& stages, std::size_t stage_count) : s_(stages), n_(stages.size()), k_(stage_count, std::vector<double>(n_)), tmp_(n_) {}
  bool start(double, const double*) { return true; }
  void accept() {}
  const std::optional<StepFailure>& failure() const { return no_step_failure(); }
  void add_stats(SolverStats&) const {}

 protected:
  /// k_[stage] = f(t, y), and power_[stage] the witness's rates there.
  bool eval(double t, const double* y, std::size_t stage) {
    return s_.derivative(t, y, k_[stage].data(), s_.witness() ? power_[stage] : nullptr);
  }
  /// tmp_ = y + a k_[stage]
  const double* axpy(const double* y, double a, std::size_t stage) {
    const std::vector<double>& k = k_[stage];
    for (std::size_t i = 0; i < n_; ++i) tmp_[i] = y[i] + a * k[i];
    return tmp_.data();
  }

  Stages& s_;
  std::size_t n_;
  std::vector<std::vector<double>> k_;  ///< the stages' derivatives
  std::vector<double> tmp_;             ///< a stage's state
  double power_[4][2] = {};             ///< the witness's rates at the stages
};

/// Explicit (forward) Euler, order 1: y1 = y + h f(t, y).
class Euler : Explicit {
 public:
  static constexpr const char* kName = "euler";
  Euler(Stages& stages, const Settings&) : Explicit(stages, 1) {}
  using Explicit::accept, Explicit::add_stats, Explicit::failure, Explicit::start;
  std::string description(double h) const { return fmt::format("explicit Euler, fixed step {:g} s", h); }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    if (!eval(t, y, 0)) return false;
    std::copy_n(axpy(y, h, 0), n_, out);
    for (int k = 0; k < 2; ++k) energy[k] = h * power_[0][k];
    return true;
  }
};

/// Heun (explicit trapezoidal rule, RK2), order 2.
class Heun : Explicit {
 public:
  static constexpr const char* kName = "heun";
  Heun(Stages& stages, const Settings&) : Explicit(stages, 2) {}
  using Explicit::accept, Explicit::add_stats, Explicit::failure, Explicit::start;
  std::string description(double h) const { return fmt::format("Heun (RK2), fixed step {:g} s", h); }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    if (!eval(t, y, 0) || !eval(t + h, axpy(y, h, 0), 1)) return false;
    for (std::size_t i = 0; i < n_; ++i) out[i] = y[i] + h / 2 * (k_[0][i] + k_[1][i]);
    for (int k = 0; k < 2; ++k) energy[k] = h / 2 * (power_[0][k] + power_[1][k]);
    return true;
  }
};

/// The classic Runge-Kutta of order 4: the method for real-time loops
/// where a predictable cost per step matters more than error control.
class Rk4 : Explicit {
 public:
  static constexpr const char* kName = "rk4";
  Rk4(Stages& stages, const Settings&) : Explicit(stages, 4) {}
  using Explicit::accept, Explicit::add_stats, Explicit::failure, Explicit::start;
  std::string description(double h) const { return fmt::format("classic Runge-Kutta 4, fixed step {:g} s", h); }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    if (!eval(t, y, 0) || !eval(t + h / 2, axpy(y, h / 2, 0), 1) || !eval(t + h / 2, axpy(y, h / 2, 1), 2) ||
        !eval(t + h, axpy(y, h, 2), 3))
      return false;
    const std::vector<double>&k1 = k_[0], &k2 = k_[1], &k3 = k_[2], &k4 = k_[3];
    for (std::size_t i = 0; i < n_; ++i) out[i] = y[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    for (int k = 0; k < 2; ++k)
      energy[k] = h / 6 * (power_[0][k] + 2 * power_[1][k] + 2 * power_[2][k] + power_[3][k]);
    return true;
  }
};

/// Semi-implicit (symplectic) Euler, order 1, for models whose unknowns are
/// positions and velocities (Model::unknown_role): the velocities first,
/// from the forces at the step's start, then the positions from the new
/// velocities. For a conservative mechanical model its energy error stays
/// bounded over any number of periods instead of growing like explicit
/// Euler's.
class SymplecticEuler : Explicit {
 public:
  static constexpr const char* kName = "symplectic_euler";
  SymplecticEuler(Stages& stages, const Settings&) : Explicit(stages, 2) {
    for (std::size_t i = 0; i < n_; ++i)
      (stages.model().model().unknown_role(i) == UnknownRole::velocity ? velocities_ : positions_).push_back(i);
  }
  using Explicit::accept, Explicit::failure, Explicit::start;
  std::string description(double h) const {
    return fmt::format("semi-implicit (symplectic) Euler, fixed step {:g} s: {} velocities, then {} positions{}", h,
                       velocities_.size(), positions_.size(),
                       s_.model().model().has_position_rates() ? " from the model's position rates" : "");
  }
  void add_stats(SolverStats& st) const { st.position_evals = s_.position_evaluations(); }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    if (!eval(t, y, 0)) return false;
    std::copy_n(y, n_, tmp_.begin());
    for (std::size_t i : velocities_) tmp_[i] += h * k_[0][i];
    if (!s_.position_rates(t + h, tmp_.data(), k_[1].data())) return false;
    for (std::size_t i : velocities_) out[i] = tmp_[i];
    for (std::size_t i : positions_) out[i] = y[i] + h * k_[1][i];
    for (int k = 0; k < 2; ++k) energy[k] = h * power_[0][k];
    return true;
  }

 private:
  std::vector<std::size_t> velocities_, positions_;
};

}  // namespace

std::unique_ptr<Integrator> make_euler(GuardedModel& model, const Settings& s) { return make_fixed_step<Euler>(model, s); }
std::unique_ptr<Integrator> make_heun(GuardedModel& model, const Settings& s) { return make_fixed_step<Heun>(model, s); }
std::unique_ptr<Integrator> make_rk4(GuardedModel& model, const Settings& s) { return make_fixed_step<Rk4>(model, s); }
std::unique_ptr<Integrator> make_symplectic_euler(GuardedModel& model, const Settings& s) {
  return make_fixed_step<SymplecticEuler>(model, s);
}

}  // namespace mbgrt::detail
