// solvers/iteration_matrix.hpp — the matrix I - c J of the fixed-step
// implicit methods (linearly_implicit.cpp, generalized_alpha.cpp), factored
// once and solved against many right-hand sides. J = df/dy is the model's
// generated Jacobian where mbgc gives one (Model::has_jacobian), else
// forward differences, a column per derivative evaluation.
#pragma once

#include <Eigen/Dense>

#include <cstddef>
#include <vector>

#include "fixed_step.hpp"

namespace mbgrt::detail {

class IterationMatrix {
 public:
  explicit IterationMatrix(Stages& stages);

  /// J at (t, y), where f(t, y) = ydot (the differences' base point). False
  /// (the guard's blame set) if the model failed there.
  bool jacobian(double t, const double* y, const double* ydot);
  /// I - c J, factored (LU with partial pivoting), unless it already is for
  /// this c and this J. False if it is singular.
  bool factor(double c);
  /// b = (I - c J)^-1 b.
  void solve(double* b);

  bool generated() const { return generated_; }
  long jacobians() const { return jacobians_; }
  long difference_evaluations() const { return difference_evaluations_; }
  long factorizations() const { return factorizations_; }

 private:
  Stages& s_;
  std::size_t n_;
  bool generated_;
  Eigen::MatrixXd j_, m_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::VectorXd x_;
  std::vector<double> row_major_, y_, f_;  // the model's J; the perturbed state and its derivative
  long jacobians_ = 0, difference_evaluations_ = 0, factorizations_ = 0;
  double factored_ = 0.0;  ///< the c of the factored I - c J (0: none)
};

/// What a failed factorization means, for the run report.
StepFailure singular_matrix(const char* method, double c);

}  // namespace mbgrt::detail
