// simulate.hpp — one run of a model from the command line's options: the
// parameters set, a consistent start, the integration over the output grid
// with its CSV, then the run summary and, if it stopped, why. run_main calls
// it once; a parameter sweep once per case, on its own model instance.
#pragma once

#include <atomic>
#include <cstdio>
#include <vector>

#include "cli.hpp"
#include "csv.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

/// Each output's last, smallest and largest value over the rows written
/// (what a sweep's summary reports of a case).
struct OutputRanges {
  std::vector<double> final, min, max;
  long rows = 0;
  void add(const std::vector<double>& row);
};

/// Where a run reports besides its CSV.
struct RunHooks {
  std::FILE* report = stderr;      ///< the run summary (unless --quiet) and the stop message
  OutputRanges* ranges = nullptr;  ///< filled at every row, if given
  bool progress = false;           ///< a progress line on stderr (the caller checks it is a terminal)
  const std::atomic<int>* stop = nullptr;  ///< a caught stop signal (interrupt.hpp) ends the run after a row
};

/// --set: false (and an error printed) for an unknown parameter.
bool apply_overrides(Model& model, const Options& o);
/// false (and an error printed) for a solver that cannot integrate the model.
bool check_model_fits(const Model& model, const Options& o);

/// The run; returns the exit status (kExitSuccess or kExitRunFailed; 128 + N
/// when hooks.stop saw signal N, as shells report a process a signal ended).
int simulate(Model& model, const Options& o, OutputFile& out, OutputFile* constraint_out, OutputFile* event_out,
             const RunHooks& hooks = {});

}  // namespace mbgrt::detail
