// The simulator command line (docs/cli.md). Parsing only: nothing here touches
// the model except to read its defaults and names.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mbgrt/model.hpp"
#include "messages.hpp"

namespace mbgrt::detail {

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitRunFailed = 1;  ///< solver failure or divergence
inline constexpr int kExitUsage = 2;      ///< bad command line or bad option value
inline constexpr int kExitInterrupted = 130;  ///< a sweep stopped by Ctrl-C (128 + SIGINT, as shells report it)

/// --sweep NAME=FROM:TO:COUNT: COUNT values from FROM to TO, evenly spaced.
struct SweepAxis {
  std::string name;
  double from = 0, to = 0;
  long count = 1;
  double value(long k) const { return count == 1 ? from : from + (to - from) * static_cast<double>(k) / static_cast<double>(count - 1); }
};

inline constexpr long kMaxSweepCases = 1'000'000;

struct Options {
  Settings settings;
  std::vector<std::pair<std::string, double>> overrides;  ///< --set, in command-line order
  std::string out_path;                                   ///< empty: stdout
  std::string constraint_report_path;                     ///< --constraint-report; empty: none
  std::string event_log_path;                             ///< --event-log; empty: none
  std::string animate_path;                               ///< --animate: the bodies' motion as glTF; empty: none
  bool quiet = false;
  bool list_parameters = false;
  std::optional<double> linearize_at;
  bool work_precision = false;  ///< --work-precision: sweep solvers and tolerances, CSV of cost and error
  bool fd_jacobian = false;     ///< --fd-jacobian: finite differences even where the model has a Jacobian
  bool strict = false;  ///< --strict: a suspect start (penetration.hpp) is an error
  bool no_energy_witness = false;  ///< --no-energy-witness: do not integrate the model's powers (energy_witness.hpp)
  std::optional<double> realtime;  ///< --realtime [FACTOR]: pace the rows to FACTOR x the wall clock
  std::vector<SweepAxis> sweep;    ///< --sweep, in command-line order (the first varies slowest)
  std::string sweep_file;          ///< --sweep-file: one case per row
  std::string case_dir;            ///< --case-dir: each case's CSV and run report
  unsigned jobs = 0;               ///< --jobs: threads for a sweep (0: one per core)
  bool sweeping() const { return !sweep.empty() || !sweep_file.empty(); }
  std::string accuracy_note;       ///< what --accuracy chose, and why (accuracy.hpp); set by the run, not parsed
};

/// Options to run with, or the exit status to return at once (after --help,
/// or after a usage error that has already been reported on stderr).
struct ParseOutcome {
  std::optional<Options> options;
  int exit_status = kExitSuccess;
};

ParseOutcome parse_command_line(const Model& model, int argc, char** argv);

}  // namespace mbgrt::detail
