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
//
// After a solver failed where a looser atol would not (a Newton iteration
// chasing rounding noise), the absolute part gets a floor, what the model's
// arithmetic can resolve:
//
//   atol_i = max(atol nominal_i, kRoundingFloor u peak_G)
//
// u the unit roundoff and peak_G the largest |y|_G the run has had so far: an
// unknown is computed from terms as large as its vector has been, so its
// rounding noise is some u times that, and asking for less makes a Newton
// iteration chase the noise (Andrews' squeezer at rtol 1e-10, atol 1e-14:
// 4e-21 asked of an angular momentum that passes through 0 stopped IDA at
// t = 0.0095 s; a factor 1e3 on u was still too little). The floor is not on
// from the start: at a zero crossing it loosens a scalar's tolerance, and a
// pendulum's energy then drifted by 1.2e-10 instead of 1e-10 at atol 1e-13.
// The unknowns it held are named in the run summary (floored()).
//
// Where even the floor leaves a tolerance below what the solver can meet (a
// Newton iteration that fails at every step size), the solver may loosen()
// every tolerance from there on, and says so.
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
  /// atol x nominal_i, per unknown (before the floor).
  const std::vector<double>& absolute() const { return atol_; }
  /// The unknowns whose tolerance the floor set at some step (it exceeded
  /// both atol x nominal and the relative part), ascending.
  std::vector<std::size_t> floored() const;
  /// From now on, the floor (see above); the peaks count from the start.
  void engage_floor() { floor_on_ = true; }
  bool floor_engaged() const { return floor_on_; }
  /// Every tolerance (relative and absolute) times factor from now on.
  void loosen(double factor) { scale_ *= factor; }
  /// The factor on the asked tolerances (1 unless loosened).
  double scale() const { return scale_; }
  /// The tightest rtol every run is expected to meet whatever its rounding:
  /// IDA loosens a tighter one where it fails (up to this one), and a joint
  /// row that must hold is never held to less than at this one
  /// (held_row_bound).
  static constexpr double kResolvedRtol = 1e-9;
  /// The floor's factor on u times the group's peak size.
  static constexpr double kRoundingFloor = 1e4;
  /// The first member of unknown i's group (Model::unknown_group, checked).
  std::size_t group(std::size_t i) const { return group_[i]; }

 private:
  double rtol_ = 0.0;
  std::vector<double> atol_;
  std::vector<std::size_t> group_;  ///< per unknown: its group's first member
  mutable std::vector<double> norm_;  ///< per group's first member: the squared norm, then the norm
  mutable std::vector<double> peak_;  ///< per group's first member: the largest norm so far
  mutable std::vector<char> floored_;  ///< per unknown: the floor set its tolerance once
  bool floor_on_ = false;
  double scale_ = 1.0;  ///< on rtol_ and atol_ (loosen)
};

}  // namespace mbgrt::detail
