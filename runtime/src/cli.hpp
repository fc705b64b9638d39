// The simulator command line (DESIGN §9). Parsing only: nothing here touches
// the model except to read its defaults and names.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mbgrt/model.hpp"

namespace mbgrt::detail {

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitRunFailed = 1;  ///< solver failure or divergence
inline constexpr int kExitUsage = 2;      ///< bad command line or bad option value

struct Options {
  Settings settings;
  std::vector<std::pair<std::string, double>> overrides;  ///< --set, in command-line order
  std::string out_path;                                   ///< empty: stdout
  std::string constraint_report_path;                     ///< --constraint-report; empty: none
  std::string event_log_path;                             ///< --event-log; empty: none
  bool quiet = false;
  bool list_parameters = false;
  std::optional<double> linearize_at;
  bool work_precision = false;  ///< --work-precision: sweep solvers and tolerances, CSV of cost and error
  bool fd_jacobian = false;     ///< --fd-jacobian: finite differences even where the model has a Jacobian
  std::optional<double> realtime;  ///< --realtime [FACTOR]: pace the rows to FACTOR x the wall clock
};

/// Options to run with, or the exit status to return at once (after --help,
/// or after a usage error that has already been reported on stderr).
struct ParseOutcome {
  std::optional<Options> options;
  int exit_status = kExitSuccess;
};

ParseOutcome parse_command_line(const Model& model, int argc, char** argv);

/// Prints "mbgrt: error: <message>" on stderr.
void print_error(const std::string& message);

}  // namespace mbgrt::detail
