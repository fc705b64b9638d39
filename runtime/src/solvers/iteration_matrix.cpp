#include "iteration_matrix.hpp"

#include <cfloat>
#include <cmath>

namespace mbgrt::detail {

IterationMatrix::IterationMatrix(Stages& stages)
    : s_(stages),
      n_(stages.size()),
      generated_(stages.model().has_jacobian()),
      j_(n_, n_),
      m_(n_, n_),
      lu_(n_),
      x_(n_),
      y_(n_),
      f_(n_) {
  if (generated_) row_major_.resize(n_ * n_);
}

bool IterationMatrix::jacobian(double t, const double* y, const double* ydot) {
  ++jacobians_;
  factored_ = 0.0;
  if (generated_) {
    if (s_.model().jacobian(t, y, row_major_.data()) != 0) return false;
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t j = 0; j < n_; ++j) j_(Eigen::Index(i), Eigen::Index(j)) = row_major_[i * n_ + j];
    return true;
  }
  // Forward differences, one column at a time, each unknown moved by
  // sqrt(eps) of its size (at least of its nominal magnitude).
  const Model& model = s_.model().model();
  std::copy(y, y + n_, y_.begin());
  for (std::size_t j = 0; j < n_; ++j) {
    const double inc = std::sqrt(DBL_EPSILON) * std::max(std::abs(y[j]), model.nominal(j));
    y_[j] = y[j] + inc;
    ++difference_evaluations_;
    if (!s_.derivative(t, y_.data(), f_.data())) return false;
    const double step = y_[j] - y[j];  // (the increment as represented)
    for (std::size_t i = 0; i < n_; ++i) j_(Eigen::Index(i), Eigen::Index(j)) = (f_[i] - ydot[i]) / step;
    y_[j] = y[j];
  }
  return true;
}

bool IterationMatrix::factor(double c) {
  if (c == factored_) return true;
  factored_ = 0.0;
  ++factorizations_;
  m_ = -c * j_;
  m_.diagonal().array() += 1.0;
  lu_.compute(m_);
  // PartialPivLU does not report a singular matrix: a zero or non-finite
  // pivot (or one at rounding level of the largest) is one.
  const Eigen::VectorXd pivots = lu_.matrixLU().diagonal().cwiseAbs();
  const double largest = lu_.matrixLU().cwiseAbs().maxCoeff();
  if (!pivots.allFinite() || !std::isfinite(largest) || !(pivots.minCoeff() > 1e3 * DBL_EPSILON * largest)) return false;
  factored_ = c;
  return true;
}

void IterationMatrix::solve(double* b) {
  Eigen::Map<Eigen::VectorXd> v(b, Eigen::Index(n_));
  x_ = lu_.solve(v);
  v = x_;
}

StepFailure singular_matrix(const char* method, double c) {
  return {failure_flag(method, "SINGULAR"),
          fmt::format("the iteration matrix I - {:.3g} J of {} is singular (J: the model's Jacobian at the step's "
                      "start); an unknown the model does not determine, or a mechanism at a singular configuration",
                      c, method)};
}

}  // namespace mbgrt::detail
