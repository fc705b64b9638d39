// sweep.hpp — a parameter study: many runs of one model, each with some
// parameters set (a grid from --sweep, or the rows of --sweep-file), spread
// over threads. Each case runs on its own model instance (Model::make_new)
// with the command line's --set first and its own values after, so a case's
// result does not depend on which thread ran it or on the cases before it:
// the summary is the same for any --jobs.
//
// The summary (--out, stdout by default) has one row per case, in case order:
//   case,<parameters>,status,<output>_final,<output>_min,<output>_max,...,wall_s,message
// status is ok or failed; a failed case's message is its first error line,
// and the cases after it still run. With --case-dir DIR each case also
// writes DIR/case_NNNN.csv (its trajectory, as a single run's --out) and
// DIR/case_NNNN.log (what a single run prints on stderr).
#pragma once

#include <string>
#include <vector>

#include "cli.hpp"
#include "csv.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// The cases: parameter names, and one row of values per case.
struct SweepPlan {
  std::vector<std::string> names;
  std::vector<std::vector<double>> cases;
};

/// Every combination of the axes' values, the first axis varying slowest.
SweepPlan grid_plan(const std::vector<SweepAxis>& axes);
/// A CSV file: a header of parameter names, then one row of numbers per case
/// (blank lines and lines starting with # skipped). Throws std::runtime_error
/// with file:line for a malformed file.
SweepPlan read_sweep_file(const std::string& path);

/// Runs the sweep; the exit status: kExitSuccess if every case ran to the
/// end, kExitRunFailed if one failed, kExitUsage if it could not start.
int run_sweep(const Model& prototype, const Options& o, OutputFile& summary);

}  // namespace mbgrt::detail
