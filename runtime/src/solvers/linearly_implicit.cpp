// The linearly implicit fixed-step methods, for stiff models in real time:
// one Jacobian and one LU factorization per step and no Newton loop, so the
// cost of a step is fixed (what hardware-in-the-loop codes use).
//
//  - linearly implicit Euler, order 1:  (I - h J) k = f(t, y) + h f_t,  y1 = y + h k;
//  - ROS2 (Verwer, Spee, Blom and Hundsdorfer 1999), order 2, L-stable, with
//    g = 1 + 1/sqrt(2):
//      (I - g h J) k1 = f(t, y) + g h f_t
//      (I - g h J) k2 = f(t + h, y + h k1) - 2 k1 - g h f_t
//      y1 = y + h (3/2 k1 + 1/2 k2).
// Both are W-methods: they keep their order for any matrix J, so a Jacobian
// by differences (or one that lags) costs stability at worst, never order.
// The f_t terms are the methods applied to the model with time as an
// unknown (t' = 1), whose Jacobian has the column f_t = df/dt: without them
// a stiff model driven by time (a stiff spring on a prescribed motion) loses
// an order. f_t is a forward difference in t, one derivative more per step.
// The witness integrates the power by the rectangle rule (Euler) and the
// trapezoidal rule over the step (ROS2), each at the method's order; the
// power at a step's end is the next one's start.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <optional>
#include <vector>

#include "iteration_matrix.hpp"

namespace mbgrt::detail {

namespace {

class LinearlyImplicit {
 public:
  LinearlyImplicit(Stages& stages) : s_(stages), n_(stages.size()), matrix_(stages), f0_(n_), ft_(n_), tmp_(n_) {}
  // (a trial always starts from the accepted state: the event search's
  // trials of shorter steps reuse its derivative and Jacobian)
  bool start(double, const double*) {
    linearized_ = start_power_known_ = false;
    return true;
  }
  void accept() {
    linearized_ = false;
    // (the trapezoidal rule's end is the next step's start)
    start_power_known_ = end_power_known_;
    std::copy(power_[1], power_[1] + 2, power_[0]);
  }
  const std::optional<StepFailure>& failure() const { return failure_; }
  void add_stats(SolverStats& st) const {
    st.jac_evals = matrix_.jacobians();
    st.fd_jac_evals = matrix_.difference_evaluations() + time_differences_;
  }

 protected:
  std::string jacobian_source() const { return matrix_.generated() ? "generated" : "finite-difference"; }
  /// f0_ = f(t, y), ft_ = df/dt there and I - c J at (t, y) factored;
  /// power_[0] the witness's rates there.
  bool linearize(const char* method, double t, const double* y, double c) {
    failure_.reset();
    if (!linearized_) {
      if (!s_.derivative(t, y, f0_.data(), s_.witness() && !start_power_known_ ? power_[0] : nullptr)) return false;
      end_power_known_ = false;
      if (!matrix_.jacobian(t, y, f0_.data())) return false;
      const double dt = std::sqrt(DBL_EPSILON) * std::max(std::abs(t), 1.0);
      const double t1 = t + dt;
      ++time_differences_;
      if (!s_.derivative(t1, y, ft_.data())) return false;
      for (std::size_t i = 0; i < n_; ++i) ft_[i] = (ft_[i] - f0_[i]) / (t1 - t);
      linearized_ = true;
    }
    if (!matrix_.factor(c)) {
      failure_ = singular_matrix(method, c);
      return false;
    }
    return true;
  }

  Stages& s_;
  std::size_t n_;
  IterationMatrix matrix_;
  std::vector<double> f0_, ft_, tmp_;
  long time_differences_ = 0;
  double power_[2][2] = {};  ///< the witness's rates at the step's start and (ROS2) end
  std::optional<StepFailure> failure_;
  bool linearized_ = false;  ///< f0_, ft_ and the Jacobian are the accepted state's
  bool start_power_known_ = false, end_power_known_ = false;
};

class LinearlyImplicitEuler : LinearlyImplicit {
 public:
  static constexpr const char* kName = "linearly_implicit_euler";
  LinearlyImplicitEuler(Stages& stages, const Settings&) : LinearlyImplicit(stages) {}
  using LinearlyImplicit::accept, LinearlyImplicit::add_stats, LinearlyImplicit::failure, LinearlyImplicit::start;
  std::string description(double h) const {
    return fmt::format("linearly implicit Euler, fixed step {:g} s, {} Jacobian", h, jacobian_source());
  }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    if (!linearize(kName, t, y, h)) return false;
    for (std::size_t i = 0; i < n_; ++i) tmp_[i] = f0_[i] + h * ft_[i];
    matrix_.solve(tmp_.data());
    for (std::size_t i = 0; i < n_; ++i) out[i] = y[i] + h * tmp_[i];
    for (int k = 0; k < 2; ++k) energy[k] = h * power_[0][k];
    return true;
  }
};

class Ros2 : LinearlyImplicit {
 public:
  static constexpr const char* kName = "ros2";
  Ros2(Stages& stages, const Settings&) : LinearlyImplicit(stages), k1_(n_), k2_(n_) {}
  using LinearlyImplicit::accept, LinearlyImplicit::add_stats, LinearlyImplicit::failure, LinearlyImplicit::start;
  std::string description(double h) const {
    return fmt::format("ROS2 (Rosenbrock-W, order 2), fixed step {:g} s, {} Jacobian", h, jacobian_source());
  }

  bool trial(double t, const double* y, double h, double* out, double* energy) {
    const double g = 1.0 + 1.0 / std::sqrt(2.0);
    if (!linearize(kName, t, y, g * h)) return false;
    for (std::size_t i = 0; i < n_; ++i) k1_[i] = f0_[i] + g * h * ft_[i];
    matrix_.solve(k1_.data());
    for (std::size_t i = 0; i < n_; ++i) tmp_[i] = y[i] + h * k1_[i];
    if (!s_.derivative(t + h, tmp_.data(), k2_.data())) return false;
    for (std::size_t i = 0; i < n_; ++i) k2_[i] -= 2 * k1_[i] + g * h * ft_[i];
    matrix_.solve(k2_.data());
    for (std::size_t i = 0; i < n_; ++i) out[i] = y[i] + h * (1.5 * k1_[i] + 0.5 * k2_[i]);
    if (s_.witness()) {
      s_.power(t + h, out, power_[1]);
      end_power_known_ = true;
      for (int k = 0; k < 2; ++k) energy[k] = h / 2 * (power_[0][k] + power_[1][k]);
    }
    return true;
  }

 private:
  std::vector<double> k1_, k2_;
};

}  // namespace

std::unique_ptr<Integrator> make_linearly_implicit_euler(GuardedModel& model, const Settings& s) {
  return make_fixed_step<LinearlyImplicitEuler>(model, s);
}
std::unique_ptr<Integrator> make_ros2(GuardedModel& model, const Settings& s) { return make_fixed_step<Ros2>(model, s); }

}  // namespace mbgrt::detail
