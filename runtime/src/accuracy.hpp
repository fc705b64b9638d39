// --accuracy TOL (and `simulate { accuracy = TOL }`): a run that picks its
// own method. A probe runs the model over the whole run with every
// integrator that fits it, each from its cheapest setting (the longest step,
// the loosest tolerance: the work-precision sweep's, work_precision.hpp)
// towards finer ones, measures each run's error against a reference and its
// wall time, and keeps the cheapest that meets TOL; the run is then made with
// it, and the run summary says what it chose, why, and the error measured.
//
// The error is the work-precision sweep's: the largest |y - y_ref| over the
// outputs and the output times, each output scaled by its largest |y_ref|
// (but no less than the model's atol / rtol). The reference is Dormand-Prince
// (IDA for a DAE) at TOL / 1000, and no looser than its own error allows:
// its error, estimated against a run at 10 x its rtol, is counted into every
// measurement. The probe covers the whole run because a prefix would miss
// what happens later (a contact's first impact, a lane change): the cost of
// that is the probe's wall time, which the summary gives beside the run's.
#pragma once

#include <optional>
#include <string>

#include "mbgrt/model.hpp"

namespace mbgrt::detail {

struct AccuracyChoice {
  Settings settings;  ///< `base` with the chosen solver and step or tolerances
  std::string note;   ///< the run summary's `accuracy` line: the choice, why, the error measured
};

/// The setting for `base` (the run as asked, its solver ignored) that meets
/// `tolerance` at the least cost; nullopt, with the reason printed, when the
/// reference run fails or no setting meets it.
std::optional<AccuracyChoice> choose_for_accuracy(Model& model, const Settings& base, double tolerance);

}  // namespace mbgrt::detail
