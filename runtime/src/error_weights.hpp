// The adaptive integrators' error weights, per unknown i:
//
//   w_i = 1 / (rtol max(|y_i|, 0.1 |y|_G) + atol nominal_i)
//
// where G is unknown i's group (Model::unknown_group: the components of one
// multibond storage, a body's momentum or position vector) and |y|_G the
// 2-norm of the group's entries. The relative part measures a component
// against its own size but never against less than a tenth of its vector's
// (a planar mechanism's out-of-plane momentum, zero but for rounding, is not
// held to an absolute tolerance of its own; measuring every component
// against the whole vector's size cost the pendulum's 1000-s energy drift a
// factor 2). The absolute part scales with the unknown's nominal size
// (Model::nominal: a momentum's inertia, so that atol bounds a velocity).
// With no groups and no nominal sizes this is SUNDIALS' own
// 1 / (rtol |y_i| + atol).
#pragma once

#include <cstddef>
#include <vector>

#include "mbgrt/model.hpp"

namespace mbgrt::detail {

class ErrorWeights {
 public:
  ErrorWeights() = default;
  ErrorWeights(const Model& model, double rtol, double atol);

  /// w from y (n entries each); false if a tolerance is not positive (the
  /// integrator then reports a bad weight, as with its own).
  bool operator()(const double* y, double* w) const;
  /// atol x nominal_i, per unknown.
  const std::vector<double>& absolute() const { return atol_; }
  /// The first member of unknown i's group (Model::unknown_group, checked).
  std::size_t group(std::size_t i) const { return group_[i]; }

 private:
  double rtol_ = 0.0;
  std::vector<double> atol_;
  std::vector<std::size_t> group_;  ///< per unknown: its group's first member
  mutable std::vector<double> norm_;  ///< per group's first member: the squared norm, then the norm
};

}  // namespace mbgrt::detail
