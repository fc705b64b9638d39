#include "energy_witness.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "report.hpp"

namespace mbgrt::detail {

void EnergyWitness::observe(double t, const double* y, const double* yp, const double* energy) {
  if (!active() || !energy) return;
  guard_.model().stored_energy(t, y, yp, &h_);
  supplied_ = energy[0];
  absorbed_ = energy[1];
  jumped_ = guard_.events().jumped_energy();
  if (!started_) h0_ = h_, started_ = true;
  residual_ = h_ - h0_ - supplied_ + absorbed_ + jumped_;
  if (!(std::abs(residual_) <= worst_)) worst_ = std::abs(residual_), worst_t_ = t;  // (a NaN is the worst)
  scale_ = std::max({scale_, std::abs(h_), std::abs(supplied_), std::abs(absorbed_ + jumped_)});
}

std::string EnergyWitness::summary() const {
  std::string s = fmt::format("residual {:.2g} J at most (t = {} s), of {:.3g} J in play; stored {:.9g} J from {:.9g} J, "
                              "supplied {:.9g} J, absorbed {:.9g} J",
                              worst_, format_time(worst_t_), scale_, h_, h0_, supplied_, absorbed_);
  if (jumped_ != 0.0) s += fmt::format(", taken by jumps {:.6g} J", jumped_);
  if (!std::isnan(guard_.witness_broken_at()))
    s += fmt::format(" (the power was not finite from t = {} s on: counted as 0)", format_time(guard_.witness_broken_at()));
  return s;
}

std::string EnergyWitness::warning(double rtol) const {
  // what rtol asks of the energy in play, never less than what the balance
  // can hold: its integrals follow the states' steps without an error test of
  // their own, so below kTightestRtol its drift stops shrinking with rtol; a
  // dissipative run only (a conservative model's drift is the method's known
  // character, and what the summary's energy line shows)
  const double asked = std::max(rtol, kTightestRtol) * scale_;
  if (!(absorbed() > kDissipative * scale_) || !(worst_ > kWarnFactor * asked)) return {};
  const std::string drift = fmt::format("the energy balance drifts by {:.2g} J (t = {} s), {:.0f} times rtol x the {:.3g} J in play",
                                        worst_, format_time(worst_t_), worst_ / (rtol * scale_), scale_);
  if (rtol <= kTightestRtol)
    return fmt::format("{}, more than a tolerance this tight explains: look for a discontinuity where the power jumps (a "
                       "step, a friction law) or compare with a run at a fixed --step",
                       drift);
  // the residual grows about as rtol does: the rtol that brings it to `asked`
  const double needed = std::pow(10.0, std::floor(std::log10(rtol * asked / worst_)));
  if (needed < kFinestRtol)
    return fmt::format("{}: holding it to rtol x the energy would take rtol {:g}, finer than a run in double precision holds", drift,
                       needed);
  return fmt::format("{}: rerun with --rtol {:g} or tighter to hold it", drift, needed);
}

}  // namespace mbgrt::detail
