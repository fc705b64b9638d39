// Unilateral contacts that start inside their surface. Such a contact starts
// closed, and its row's stabilisation pushes the bodies apart: energy the
// model never had, added in the first moments of the run (Contacts holds it
// closed until it is out). A start deeper than the run's absolute tolerance
// is a warning (an error under --strict) naming the contact and its depth;
// once the contact is pushed back to within a thousandth of its depth (or
// opens), the run summary says how much energy that added:
// what the model absorbed meanwhile, negated (Model::power; the energy
// witness integrates it), so any damping acting meanwhile is counted in too.
// A compliant contact that starts inside holds its spring's energy in the
// balance: not reported.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "events.hpp"

namespace mbgrt::detail {

class StartPenetrations {
 public:
  /// After Events::start: the unilateral contacts whose gap is below -tolerance (m).
  StartPenetrations(Events& events, double tolerance);
  bool any() const { return !found_.empty(); }
  /// One line per contact: "contact hit (ball.mbg:33:9) starts 0.3 m inside its surface (gap -0.3 m; ...)".
  std::vector<std::string> describe() const;
  /// At an output point, the energy the model has absorbed since the start
  /// (EnergyWitness::absorbed; NaN: no witness): settles the contacts pushed
  /// back within the tolerance, or opened, by now.
  void observe(double t, const double* y, double absorbed);
  /// The summary's lines: "contact hit: pushing it out of its surface added 2.87 J by t = 0.066 s".
  std::vector<std::string> summary() const;

 private:
  struct Found {
    std::size_t contact = 0;
    double depth = 0.0;          ///< -gap at the start (m)
    double settled_t = NAN;      ///< when it was first within the tolerance or open (NaN: not yet)
    double added = NAN;          ///< energy added by then (J; NaN: unknown)
  };
  Events& events_;
  double tolerance_;
  std::vector<Found> found_;
};

}  // namespace mbgrt::detail
