// Generalized-alpha (Chung and Hulbert 1993) in its form for first-order
// systems y' = f(t, y) (Jansen, Whiting and Hulbert 2000), the method
// flexible-multibody codes use to damp the modes a scene does not resolve.
// With the algorithmic rate v_n (v_0 = f(t_0, y_0)), each step solves for
// v_{n+1}:
//
//   y_{n+1}   = y_n + h ((1 - gamma) v_n + gamma v_{n+1})
//   v_{n+am}  = v_n + alpha_m (v_{n+1} - v_n)
//   y_{n+af}  = y_n + alpha_f (y_{n+1} - y_n)
//   v_{n+am}  = f(t_n + alpha_f h, y_{n+af})
//
// with alpha_m = (3 - rho) / (2 (1 + rho)), alpha_f = 1 / (1 + rho) and
// gamma = 1/2 + alpha_m - alpha_f: second order, unconditionally stable for
// linear problems, and rho (--rho-inf, in [0, 1]) the spectral radius at an
// infinite step: 1 keeps every mode (the trapezoidal rule), 0 annihilates
// the modes far above 1/h in one step, the low ones kept to second order.
//
// Newton's method on v_{n+1} with the matrix alpha_m (I - c J), until the
// correction moves y_{n+1} by less than 1e-10 of its size (or v_{n+1} by
// less than its rounding),
// c = alpha_f gamma h / alpha_m, J = df/dy: J is kept from step to step
// (modified Newton); where that does not converge, the step is taken again
// with J evaluated at every iterate (a contact closing stiffens the model
// within the step). The witness integrates the power by the trapezoidal rule.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <optional>
#include <vector>

#include "iteration_matrix.hpp"

namespace mbgrt::detail {

namespace {

class GeneralizedAlpha {
 public:
  static constexpr const char* kName = "generalized_alpha";
  GeneralizedAlpha(Stages& stages, const Settings& s)
      : s_(stages),
        n_(stages.size()),
        rho_(s.rho_inf),
        alpha_m_((3 - rho_) / (2 * (1 + rho_))),
        alpha_f_(1 / (1 + rho_)),
        gamma_(0.5 + alpha_m_ - alpha_f_),
        matrix_(stages),
        v_(n_),
        v_trial_(n_),
        y_f_(n_),
        f_(n_),
        r_(n_) {}

  std::string description(double h) const {
    return fmt::format("generalized-alpha (rho_inf {:g}: alpha_m {:.4g}, alpha_f {:.4g}, gamma {:.4g}), fixed step "
                       "{:g} s, {} Jacobian",
                       rho_, alpha_m_, alpha_f_, gamma_, h, matrix_.generated() ? "generated" : "finite-difference");
  }

  /// The algorithmic rate starts as the model's derivative (at the run's
  /// start and after every event, whose jump or switch changed it).
  bool start(double t, const double* y) {
    return s_.derivative(t, y, v_.data(), s_.witness() ? power_ : nullptr);
  }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    failure_.reset();
    for (int attempt = 0; attempt < 2; ++attempt) {
      std::copy(v_.begin(), v_.end(), v_trial_.begin());
      bool converged = false;
      for (int it = 0; it < kIterations && !converged; ++it) {
        // the step's end and its alpha_f point for this v_{n+1}
        for (std::size_t i = 0; i < n_; ++i) {
          out[i] = y[i] + h * ((1 - gamma_) * v_[i] + gamma_ * v_trial_[i]);
          y_f_[i] = y[i] + alpha_f_ * (out[i] - y[i]);
        }
        const double t_f = t + alpha_f_ * h;
        if (!s_.derivative(t_f, y_f_.data(), f_.data())) return false;
        if (!has_jacobian_ || attempt > 0) {  // (the second attempt: Newton's method in full)
          if (!matrix_.jacobian(t_f, y_f_.data(), f_.data())) return false;
          has_jacobian_ = true;
        }
        const double c = alpha_f_ * gamma_ * h / alpha_m_;
        if (!matrix_.factor(c)) {
          failure_ = singular_matrix(kName, c);
          return false;
        }
        // -r / alpha_m, r = v_{n+am} - f(t_f, y_f)
        for (std::size_t i = 0; i < n_; ++i) r_[i] = -(v_[i] + alpha_m_ * (v_trial_[i] - v_[i]) - f_[i]) / alpha_m_;
        matrix_.solve(r_.data());  // the correction to v_{n+1}
        ++iterations_;
        // converged once the correction moves y_{n+1} by less than 1e-10 of
        // its size, or v_{n+1} by less than its rounding (a stiff model's
        // rate is large where its state is not)
        double worst = 0.0;
        for (std::size_t i = 0; i < n_; ++i) {
          const double scale = std::max(std::abs(out[i]), s_.model().model().nominal(i));
          const double moved = std::abs(h * gamma_ * r_[i]) / scale;
          if (std::abs(r_[i]) > 4 * DBL_EPSILON * std::abs(v_trial_[i])) worst = std::max(worst, moved);
          v_trial_[i] += r_[i];
          if (!std::isfinite(moved)) worst = moved;
        }
        if (!std::isfinite(worst)) break;
        converged = worst <= kTolerance;
      }
      if (converged) {
        for (std::size_t i = 0; i < n_; ++i) out[i] = y[i] + h * ((1 - gamma_) * v_[i] + gamma_ * v_trial_[i]);
        if (s_.witness()) {
          s_.power(t + h, out, power_trial_);
          for (int k = 0; k < 2; ++k) energy[k] = h / 2 * (power_[k] + power_trial_[k]);
        }
        return true;
      }
      ++slow_;
    }
    failure_ = StepFailure{
        failure_flag(kName, "NEWTON"),
        fmt::format("Newton's iteration did not converge in {} iterations, even with a Jacobian at each: the step is too "
                    "large for the model's nonlinearity here; try a smaller --step",
                    kIterations)};
    return false;
  }

  void accept() {
    v_.swap(v_trial_);
    std::copy(power_trial_, power_trial_ + 2, power_);
  }
  const std::optional<StepFailure>& failure() const { return failure_; }
  void add_stats(SolverStats& st) const {
    st.jac_evals = matrix_.jacobians();
    st.fd_jac_evals = matrix_.difference_evaluations();
    st.nonlin_iters = iterations_;
    st.nonlin_conv_fails = slow_;
  }

 private:
  static constexpr int kIterations = 8;
  static constexpr double kTolerance = 1e-10;

  Stages& s_;
  std::size_t n_;
  double rho_, alpha_m_, alpha_f_, gamma_;
  IterationMatrix matrix_;
  bool has_jacobian_ = false;  ///< J is kept from step to step
  std::vector<double> v_, v_trial_, y_f_, f_, r_;
  double power_[2] = {}, power_trial_[2] = {};  ///< the witness's rates at the step's start and end
  long iterations_ = 0, slow_ = 0;
  std::optional<StepFailure> failure_;
};

}  // namespace

std::unique_ptr<Integrator> make_generalized_alpha(GuardedModel& model, const Settings& s) {
  return make_fixed_step<GeneralizedAlpha>(model, s);
}

}  // namespace mbgrt::detail
