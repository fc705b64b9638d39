#include "report.hpp"

#include <algorithm>

#include <fmt/format.h>

#include <string_view>

namespace mbgrt::detail {

namespace {

bool flag_is(const std::string& flag, std::string_view suffix) { return flag.ends_with(suffix); }

/// What a failure most likely means for a mechanical model, and what to try.
std::string hint_for(const SolverFailure& f, std::string_view solver) {
  const std::string& flag = f.flag_name;
  const IntegratorInfo* info = find_integrator(solver);
  const bool explicit_method = info && !info->implicit;
  // the implicit integrators, those of ODEs first: "cvode (or ida)"
  std::string implicit;
  for (ModelForm form : {ModelForm::ode, ModelForm::dae})
    for (const IntegratorInfo& i : kIntegrators)
      if (i.implicit && i.adaptive && i.form == form) implicit += implicit.empty() ? i.name : fmt::format(" (or {})", i.name);
  if (flag_is(flag, "TOO_MUCH_WORK"))
    return explicit_method
               ? fmt::format("the model is probably stiff here; try --solver {}", implicit)
               : "the solution changes extremely fast or approaches a singularity near this time; "
                 "a shorter --interval also allows more steps between outputs";
  if (flag_is(flag, "TOO_MUCH_ACC")) return "loosen --rtol/--atol";
  if (flag_is(flag, "ERR_FAILURE") || flag_is(flag, "ERR_FAIL") || flag_is(flag, "CONV_FAILURE") ||
      flag_is(flag, "CONV_FAIL"))
    return "the solution probably has a singularity or a discontinuity near this time (an "
           "impact, a lock-up, a joint passing through a singular configuration); the CSV shows "
           "the approach to it";
  if (flag_is(flag, "_NONFINITE"))
    return "try a smaller --step, or an adaptive solver (--solver dopri5 or cvode)";
  if (flag_is(flag, "LINESEARCH_FAIL") || flag_is(flag, "NO_RECOVERY"))
    return "check the initial values of the algebraic variables";
  return {};
}

void note(std::FILE* err, std::string_view text) {
  if (!text.empty()) fmt::print(err, "mbgrt: note: {}\n", text);
}

}  // namespace

std::string format_time(double t) { return fmt::format("{:.9g}", t); }

/// Each stretch of time the rank-revealing solves found rows dependent, the
/// first kListed of them one a line: where a mechanism passed a change point.
void print_rank_loss_episodes(std::FILE* err, const RankLossLog& rl) {
  constexpr std::size_t kListed = 10;
  const auto& eps = rl.episodes();
  const std::size_t total = eps.size() + rl.later_episodes();
  fmt::print(err, "               in {} episode{} (rows dependent within {} s of each other):\n", total,
             total == 1 ? "" : "s", RankLossLog::kEpisodeGap);
  for (std::size_t i = 0; i < std::min(eps.size(), kListed); ++i) {
    const RankLossLog::Episode& e = eps[i];
    fmt::print(err, "               t = {} to {} s: rank {} of {}, {} implied ({} evaluation{})\n", format_time(e.begin),
               format_time(e.end), e.lowest_rank, e.size, e.rows, e.evaluations, e.evaluations == 1 ? "" : "s");
  }
  if (total > kListed) fmt::print(err, "               and {} more\n", total - kListed);
}

/// The switches of the model's events, the first kListed of them one a line.
void print_events(std::FILE* err, const Events& events) {
  constexpr std::size_t kListed = 10;
  const auto& log = events.log();
  fmt::print(err, "  events       {} switch{} of {} event{}{}\n", log.size(), log.size() == 1 ? "" : "es", events.count(),
             events.count() == 1 ? "" : "s", log.empty() ? "" : ":");
  for (std::size_t i = 0; i < std::min(log.size(), kListed); ++i) fmt::print(err, "               {}\n", events.describe(log[i]));
  if (log.size() > kListed)
    fmt::print(err, "               and {} more (--event-log FILE.csv writes them all), the last:\n"
                    "               {}\n",
               log.size() - kListed, events.describe(log.back()));
}

void print_summary(std::FILE* err, const RunRecord& run) {
  const Integrator& integ = *run.integrator;
  const SolverStats st = integ.stats();
  const Settings& s = run.settings;
  const bool residual = std::string_view(integ.name()) == "ida" && run.model->is_dae();

  fmt::print(err, "mbgrt: run summary for model '{}' ({})\n", run.model->name(),
             run.model->source_file());
  fmt::print(err, "  solver       {}: {}\n", integ.name(), integ.description());
  if (!run.accuracy.empty()) fmt::print(err, "  accuracy     {}\n", run.accuracy);
  fmt::print(err, "  time         {} s to {} s, interval {} s, reached {} s\n",
             format_time(s.t_start_s), format_time(s.t_end_s), format_time(s.interval_s),
             format_time(integ.t()));
  if (run.assembly) fmt::print(err, "  assembly: {}\n", describe(*run.assembly));
  if (run.redundancy)
    fmt::print(err, "  redundant constraints: {}\n", describe(*run.redundancy, *run.model));
  if (run.initial_values)
    fmt::print(err, "  initial values: {}\n",
               describe(*run.initial_values, run.constraints ? run.constraints->shape()
                                                             : constraint_shape(*run.model)));
  fmt::print(err, "  steps        {} (last step {:.3g} s)\n", st.steps, st.last_step);
  if (!run.stability.empty()) fmt::print(err, "  stability    {}\n", run.stability);
  if (!run.small_states.empty()) fmt::print(err, "  tolerance    {}\n", run.small_states);
  if (!run.floored.empty()) fmt::print(err, "  tolerance    {}\n", run.floored);
  if (!run.energy.empty()) fmt::print(err, "  energy       {}\n", run.energy);
  if (!run.energy_note.empty()) fmt::print(err, "  energy       {}{}\n", run.energy.empty() ? "no balance: " : "leaves out: ", run.energy_note);
  if (!run.energy_warning.empty()) fmt::print(err, "  warning      {}\n", run.energy_warning);
  for (const std::string& line : run.start_warnings) fmt::print(err, "  warning      {}\n", line);

  std::string evals = fmt::format("{} {}", st.rhs_evals, residual ? "residual" : "RHS");
  if (st.fd_jac_evals >= 0)
    evals += fmt::format(" (+ {} for finite-difference Jacobians)", st.fd_jac_evals);
  if (st.position_evals >= 0) evals += fmt::format(", {} of the position rates alone", st.position_evals);
  if (st.jac_evals >= 0) evals += fmt::format(", {} Jacobian evaluations", st.jac_evals);
  fmt::print(err, "  evaluations  {}\n", evals);

  if (st.nonlin_iters >= 0)
    fmt::print(err, "  nonlinear    {} iterations, {} convergence failures\n", st.nonlin_iters,
               st.nonlin_conv_fails);
  if (st.err_test_fails >= 0) fmt::print(err, "  error tests  {} failed\n", st.err_test_fails);
  if (st.warnings > 0)
    fmt::print(err, "  warnings     {} from the solver (first: {})\n", st.warnings,
               st.first_warning);
  if (run.constraints) fmt::print(err, "  {}\n", describe(*run.constraints));
  if (const RankLossLog* rl = run.model->rank_loss(); rl && rl->count() > 0) {
    const bool one = rl->size() - rl->lowest_rank() == 1;
    fmt::print(err,
               "  dependent rows: {} derivative evaluation{} found {} rank-deficient, first at t = {} s; "
               "lowest rank {} of {} at t = {} s, where {} {} implied by the others ({} set to 0: the basic "
               "solution)\n",
               rl->count(), rl->count() == 1 ? "" : "s", rl->system(), format_time(rl->first_t()), rl->lowest_rank(),
               rl->size(), format_time(rl->lowest_t()), rl->rows(), one ? "was" : "were",
               one ? "its multiplier" : "their multipliers");
    print_rank_loss_episodes(err, *rl);
  }
  if (run.events && run.events->count() > 0) print_events(err, *run.events);
  fmt::print(err, "  output       {}\n", run.output);
  fmt::print(err, "  wall time    {:.3g} s\n", run.wall_s);
  if (!run.realtime.empty()) fmt::print(err, "  real time    {}\n", run.realtime);
}

void print_stop_message(std::FILE* err, const GuardedModel& model, const Integrator& integrator,
                        bool solver_failed, const std::string& stiffness_note) {
  const auto& blame = model.blame();
  const SolverFailure& f = integrator.failure();
  const double t = blame ? blame->t : f.t;

  std::string line = fmt::format("mbgrt: error: at t = {} s: ", format_time(t));
  if (blame) line += model.describe(*blame) + "; ";
  else if (solver_failed && f.suspect >= 0)
    line += fmt::format("state '{}' has the largest error estimate; ",
                        model.model().variable_name(static_cast<std::size_t>(f.suspect)));
  if (solver_failed)
    line +=
        fmt::format("solver {} stopped: {} ({})", integrator.name(), f.flag_name, f.explanation);
  else
    line += fmt::format("run stopped (solver {})", integrator.name());
  fmt::print(err, "{}\n", line);

  if (solver_failed && blame && f.t != blame->t)
    note(err, fmt::format("the last accepted solution is at t = {} s", format_time(f.t)));
  if (blame && blame->site == BlameSite::constraint) {
    note(err, fmt::format("{}; the rows written before are whole, and --constraint-report FILE.csv shows the violation "
                          "growing",
                          model.row_held(blame->index)
                              ? "the joints cannot all hold here: a loop that cannot close (a link too short for where a "
                                "driver or the motion takes the others) or a mechanism carried past a dead point"
                              : "a penalty joint too soft for its loads (a higher `stiffness`), or a loop that cannot close"));
    if (const RankLossLog* rl = model.model().rank_loss(); rl && rl->count() > 0)
      note(err, fmt::format("the cut joints' rows first became dependent at t = {} s (at t = {} s, {} implied by the "
                            "others): the dead point, past which the loop stopped closing",
                            format_time(rl->first_t()), format_time(rl->lowest_t()), rl->rows()));
  }
  if (blame && blame->non_finite()) {
    // A constraint row of a lagrange DAE is named as the joint constraint.
    const ConstraintShape& shape = model.constraint_shape();
    const std::string culprit =
        blame->site == BlameSite::residual && residual_row_role(shape, blame->index).kind != RowRole::equation
            ? residual_row_name(model.model(), shape, blame->index)
            : fmt::format("'{}'", model.model().variable_name(blame->index));
    note(err,
         fmt::format("a non-finite value usually comes from a division by zero, the square root or "
                     "logarithm of a negative number, or a state growing without bound; check the "
                     "equations that involve {} near this time",
                     culprit));
  }
  if (solver_failed) note(err, hint_for(f, integrator.name()));
  note(err, stiffness_note);
  if (solver_failed && !f.solver_message.empty())
    note(err, fmt::format("solver message: {}", f.solver_message));
}

}  // namespace mbgrt::detail
