// The energy balance as a witness of a run's error, with no reference run
// (Model::has_energy_balance; compiler/reduce/energy.hpp):
//
//   residual(t) = H(t) - H(t0) - supplied(t) + absorbed(t) + jumped(t)
//
// where H is the stored energy at the output point, supplied and absorbed
// are the integrals of the model's two powers (the integrator carries them,
// Integrator::energy) and jumped is what
// the events' jumps took (Events::jumped_energy). The model's equations keep
// it at zero; what a run shows is its integration error.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "guard.hpp"

namespace mbgrt::detail {

class EnergyWitness {
 public:
  explicit EnergyWitness(GuardedModel& guard) : guard_(guard) {}
  bool active() const { return guard_.has_energy_witness(); }
  /// At an output point: the integrator's y (and yp, for a DAE) and its
  /// integrals of the two powers (Integrator::energy; null: not carried).
  void observe(double t, const double* y, const double* yp, const double* energy);

  double worst() const { return worst_; }          ///< largest |residual| over the output points (J)
  double worst_t() const { return worst_t_; }
  double residual() const { return residual_; }    ///< at the last output point
  /// The energy in play: the largest of |H|, the supplied and the absorbed energy over the run (J).
  double scale() const { return scale_; }
  double supplied() const { return supplied_; }
  double absorbed() const { return absorbed_ + jumped_; }
  /// "residual 3.1e-09 J at most (t = 2 s), of 9.8 J in play: ..." for the run summary.
  std::string summary() const;
  /// A dissipative run (the dissipators, constraints, contacts and jumps
  /// took more than kDissipative of the energy in play) whose balance drifts
  /// beyond kWarnFactor x max(rtol, kTightestRtol) x the energy in play: the
  /// warning, naming the rtol that would hold it to rtol x the energy in play
  /// (the residual taken to scale with rtol); else empty.
  std::string warning(double rtol) const;

 private:
  static constexpr double kWarnFactor = 100;    ///< residual beyond kWarnFactor x rtol x scale: warned
  static constexpr double kDissipative = 1e-3;  ///< absorbed beyond kDissipative x scale: a dissipative run
  /// The balance's integrals have no error test of their own: below this
  /// rtol its drift no longer shrinks with rtol (a damped pendulum with
  /// cvode: 1.3, 10, 75, 330 x rtol x the energy at rtol 1e-6 ... 1e-12).
  /// The warning asks no more of it than at this rtol.
  static constexpr double kTightestRtol = 1e-8;
  static constexpr double kFinestRtol = 1e-13;  ///< no rtol finer than this is named
  GuardedModel& guard_;
  bool started_ = false;
  double h0_ = 0.0, h_ = 0.0, supplied_ = 0.0, absorbed_ = 0.0, jumped_ = 0.0;
  double residual_ = 0.0, worst_ = 0.0, worst_t_ = 0.0, scale_ = 0.0;
};

}  // namespace mbgrt::detail
