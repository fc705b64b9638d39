// What the user reads on stderr: the run summary and, when a run stops
// early, a stop message that names the time, the variable and the reason.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "constraints.hpp"
#include "guard.hpp"
#include "integrator.hpp"

namespace mbgrt::detail {

struct RunRecord {
  const Model* model = nullptr;
  const Integrator* integrator = nullptr;
  Settings settings;  ///< as used (t_end_s is the --linearize-at time in that mode)
  double wall_s = 0.0;
  std::string output;  ///< e.g. "101 rows to out.csv"
  std::string stability;  ///< non-empty if an explicit solver's steps were bounded by stability
  std::string small_states;  ///< non-empty if states moved but stayed within a few atol
  std::string floored;       ///< non-empty if the rounding floor set some unknowns' tolerance (ErrorWeights)
  std::string realtime;  ///< --realtime: pacing, overruns, compute per frame
  std::string accuracy;  ///< --accuracy: what it chose, and why
  std::string energy;          ///< the energy witness's line (EnergyWitness::summary), if the model has one
  std::string energy_warning;  ///< ... and its warning (EnergyWitness::warning)
  std::string energy_note;     ///< what the balance leaves out, or why there is none (Model::energy_note)
  std::vector<std::string> start_warnings;  ///< what a suspect start did (StartPenetrations::summary)
  // Constrained models only (null otherwise):
  const AssemblyReport* assembly = nullptr;
  const RedundancyReport* redundancy = nullptr;
  const InitialValuesReport* initial_values = nullptr;
  const ConstraintMonitor* constraints = nullptr;
  const Events* events = nullptr;  ///< models with events: their switches, listed
};

void print_summary(std::FILE* err, const RunRecord& run);

/// `solver_failed` says whether the integrator itself gave up (its failure()
/// is meaningful) or the runtime stopped it (a non-finite state after a step).
/// `stiffness_note` (describe_stiffness) is printed as a note when non-empty.
void print_stop_message(std::FILE* err, const GuardedModel& model, const Integrator& integrator,
                        bool solver_failed, const std::string& stiffness_note = {});

/// Times in messages: enough digits to tell steps apart, no more.
std::string format_time(double t);

}  // namespace mbgrt::detail
