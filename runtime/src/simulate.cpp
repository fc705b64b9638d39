#include "simulate.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "animation_sink.hpp"
#include "constraints.hpp"
#include "energy_witness.hpp"
#include "error_weights.hpp"
#include "grid.hpp"
#include "guard.hpp"
#include "integrator.hpp"
#include "interrupt.hpp"
#include "linearize.hpp"
#include "march.hpp"
#include "penetration.hpp"
#include "progress.hpp"
#include "realtime.hpp"
#include "report.hpp"
#include "stiffness.hpp"

namespace mbgrt::detail {

namespace {

/// The unknowns the error weights' rounding floor held (ErrorWeights): a
/// line for the summary, empty if none.
std::string describe_floored(const Model& model, const std::vector<std::size_t>& floored) {
  if (floored.empty()) return {};
  constexpr std::size_t kListed = 4;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < std::min(kListed, floored.size()); ++k) names.push_back("'" + model.variable_name(floored[k]) + "'");
  std::string list = fmt::format("{}", fmt::join(names, ", "));
  if (floored.size() > kListed) list += fmt::format(" and {} more", floored.size() - kListed);
  return fmt::format("{} unknown{} held at the rounding floor ({}): atol x nominal asked less of {} than the "
                     "equations resolve ({:g} u x the vector's largest size)",
                     floored.size(), floored.size() == 1 ? "" : "s", list, floored.size() == 1 ? "it" : "them",
                     ErrorWeights::kRoundingFloor);
}

/// States that moved but never rose far above their absolute tolerance
/// (atol x nominal), nor did any other component of their vector
/// (Model::unknown_group): the tolerance resolves them only to that over
/// |value|. Empty if there are none.
std::string describe_small_states(const Model& model, const std::vector<double>& peak, double atol) {
  constexpr double kFactor = 100;
  const ErrorWeights weights(model, 0.0, atol);
  const std::vector<double>& a = weights.absolute();
  const std::size_t n = std::min(peak.size(), a.size());
  std::vector<double> group_peak(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) group_peak[weights.group(i)] = std::max(group_peak[weights.group(i)], peak[i]);
  std::size_t count = 0, worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(peak[i] > a[i] && group_peak[weights.group(i)] <= kFactor * a[i])) continue;
    if (count == 0 || peak[i] / a[i] < peak[worst] / a[worst]) worst = i;
    ++count;
  }
  if (count == 0) return {};
  return fmt::format("{} state{} peaked within {}x {} absolute tolerance (closest: '{}', {:.2g} against {:.2g}); "
                     "their relative error may reach {:.0f}%: lower --atol if they matter",
                     count, count == 1 ? "" : "s", kFactor, count == 1 ? "its" : "their", model.variable_name(worst),
                     peak[worst], a[worst], 100 * a[worst] / peak[worst]);
}

/// How close the multipliers' system of cut joints may come to losing rank
/// (its smallest pivot over its largest entry) before a run with an implicit
/// method is warned: measured on a row of ten four-bars, 0.075 when it swings
/// clear of its aligned configurations, 3.9e-7 when CVODE turns it through
/// them (and ends 5e-5 m off at rtol 1e-8, where dopri5 is 1e-8 off).
constexpr double kNearChangePoint = 1e-4;

/// Where the method loosened the asked tolerances (Integrator::loosenings),
/// for a note after the run; empty if nowhere.
std::string describe_loosenings(const std::vector<Integrator::Loosening>& steps, const Settings& s) {
  if (steps.empty()) return {};
  return fmt::format("the asked rtol {:g}, atol {:g} are more than this model's arithmetic resolves from "
                     "t = {} s on (IDA failed there at every step size, after its other recoveries; the "
                     "solver line lists them): the run went on from there at rtol {:g}, atol {:g}{}",
                     s.rtol, s.atol, format_time(steps.front().t_s), steps.front().rtol, steps.front().atol,
                     steps.size() == 1
                         ? std::string()
                         : fmt::format(", and from t = {} s at rtol {:g}, atol {:g}", format_time(steps.back().t_s),
                                       steps.back().rtol, steps.back().atol));
}

/// Did the method step across (Integrator::steps_across) every span where a
/// solve lost rank, and the closest approach to one?
bool stepped_across_all(const RankLossLog& rl, const std::vector<std::pair<double, double>>& spans) {
  const auto inside = [&spans](double t) {
    return std::any_of(spans.begin(), spans.end(), [t](const auto& s) { return s.first <= t && t <= s.second; });
  };
  if (spans.empty() || rl.later_episodes() > 0) return false;
  for (const RankLossLog::Episode& e : rl.episodes())
    if (!inside(e.begin) || !inside(e.end)) return false;
  return !(rl.closest() < kNearChangePoint) || inside(rl.closest_t());
}

/// An implicit multistep method that integrated near or across
/// configurations where the cut joints' rows become dependent, rather than
/// leave them to an explicit method (Integrator::steps_across: cvode and ida
/// do, solvers/carry_across.hpp, unless the rows were dependent at the start
/// and there was no independence to watch): a warning, else empty. Near such
/// a change point the multipliers' rows lose rank and a second branch of
/// motion meets the first; BDF's corrector, solving for the end of a step
/// there, can land off the branch (on the other one) without failing a test
/// (a row of four parallelogram four-bars, tests/numeric/loop_test.cpp),
/// while an explicit method only evaluates the model and steps across.
std::string implicit_near_change_points(const Model& model, Solver solver,
                                        const std::vector<std::pair<double, double>>& spans) {
  const RankLossLog* rl = model.rank_loss();
  // (a row implied by the others throughout is a redundant loop, not a change point)
  const bool rank_changed = rl && rl->cut_joint_count() > 0 && rl->cut_joint_rank_changed();
  if (!rl || !integrator_info(solver).multistep || (!rank_changed && !(rl->closest() < kNearChangePoint)) ||
      stepped_across_all(*rl, spans))
    return {};
  const std::string where =
      rank_changed
          ? fmt::format("across configurations where the cut joints' rows were dependent (the first at t = {} s; the "
                        "summary lists when)",
                        format_time(rl->cut_joint_first_t()))
            : fmt::format("near a configuration where the cut joints' rows become dependent (at t = {} s the smallest "
                          "pivot of their multipliers' system was {:.2g} of its largest entry)",
                          format_time(rl->closest_t()), rl->closest());
  return fmt::format(
      "{} integrated {}: at such a change point an implicit multistep method can carry the mechanism off its branch "
      "of motion without failing a test; an explicit method steps across (--solver dopri5, or rk4)",
      integrator_info(solver).name, where);
}

/// --event-log: one row per switch, in the order they happened.
void write_event_log(OutputFile& file, const Events& events) {
  file.write("t,event,name,state,jump,note\n");
  for (const EventRecord& e : events.log())
    file.write(fmt::format("{},{},\"{}\",{},{},\"{}\"\n", e.t, e.index, events.model_name(e.index), e.state(),
                           e.jump ? 1 : 0, e.note));
}

}  // namespace

void OutputRanges::add(const std::vector<double>& row) {
  if (rows++ == 0) {
    final = min = max = row;
    return;
  }
  for (std::size_t k = 0; k < row.size(); ++k) {
    final[k] = row[k];
    // a NaN, once seen, stays: a case whose output went non-finite must not look clean
    if (std::isnan(row[k]) || row[k] < min[k]) min[k] = row[k];
    if (std::isnan(row[k]) || row[k] > max[k]) max[k] = row[k];
  }
}

bool apply_overrides(Model& model, const Options& o) {
  for (const auto& [name, value] : o.overrides) {
    if (model.set_parameter(name, value)) continue;
    std::string known;
    for (const ParameterInfo& p : model.parameters()) known += (known.empty() ? "" : ", ") + p.name;
    print_error(fmt::format("--set {}: unknown parameter '{}'; known parameters: {}", name, name,
                            known.empty() ? "(none)" : known));
    return false;
  }
  return true;
}

/// Rejects solver/model combinations that cannot work, before any output is written.
bool check_model_fits(const Model& model, const Options& o) {
  if (model.is_dae() && !integrator_info(o.settings.solver).takes(ModelForm::dae)) {
    print_error(fmt::format("solver {} cannot integrate model '{}': it is a DAE (it has algebraic unknowns); use "
                            "--solver {}",
                            solver_name(o.settings.solver), model.name(), solver_name(kDefaultDaeSolver)));
    return false;
  }
  const std::string why = why_integrator_does_not_fit(integrator_info(o.settings.solver), model);
  if (!why.empty()) print_error(fmt::format("solver {} cannot integrate this model: {}", solver_name(o.settings.solver), why));
  return why.empty();
}

int simulate(Model& model, const Options& o, OutputFile& out, OutputFile* constraint_out, OutputFile* event_out,
             const RunHooks& hooks) {
  Settings s = o.settings;
  const bool linearize = o.linearize_at.has_value();
  if (linearize) s.t_end_s = *o.linearize_at;  // integrate only as far as the linearization point

  GuardedModel guard(model);
  if (o.fd_jacobian) guard.use_finite_differences();
  // (a linearisation reports no run; a paced run wants every microsecond of its frames)
  if (!linearize && !o.realtime && !o.no_energy_witness) guard.enable_energy_witness();
  const std::size_t n = model.size();
  std::vector<double> y0(n), yp0(model.is_dae() ? n : 0);
  model.initial(s.t_start_s, y0.data(), model.is_dae() ? yp0.data() : nullptr);
  const ConstrainedStart start = prepare_constrained_start(model, guard, s.t_start_s, y0, yp0);
  if (!start.ok) {  // nothing is integrated from a state that violates its joints
    model.terminal(s.t_start_s, y0.data());
    return kExitRunFailed;
  }
  // A unilateral contact starting inside its surface: said before the run
  // (an error under --strict), and what pushing it out added, after.
  guard.events().start(s.t_start_s, y0.data(), yp0.empty() ? nullptr : yp0.data());
  StartPenetrations penetrations(guard.events(), s.atol);
  for (const std::string& line : penetrations.describe())
    o.strict ? print_error(line + " (--strict)") : print_warning(line);
  if (penetrations.any() && o.strict) {
    model.terminal(s.t_start_s, y0.data());
    return kExitRunFailed;
  }
  guard.hold_constraints(held_row_bound(s), kHeldCeiling);
  auto integrator = make_integrator(guard, s);
  EnergyWitness witness(guard);

  CsvWriter csv(out);
  const std::vector<std::string> names = model.output_names();
  std::vector<double> outputs(names.size());
  // the CSV header: each output's name, with its unit where the model declares one
  std::vector<std::string> columns = names;
  const std::vector<std::string> units = model.output_units();
  for (std::size_t i = 0; i < columns.size() && i < units.size(); ++i)
    if (!units[i].empty()) columns[i] += " [" + units[i] + "]";
  ConstraintMonitor monitor(model, guard.constraint_shape());
  std::optional<CsvWriter> constraint_csv;
  if (constraint_out) {
    constraint_csv.emplace(*constraint_out);
    const std::vector<std::string> columns{"max_abs_g", "max_abs_gdot"};
    constraint_csv->header("t", columns);
  }
  auto observe_constraints = [&] {
    monitor.observe(integrator->t(), integrator->y());
    if (constraint_csv) {
      const double row[] = {monitor.last_position(), monitor.last_velocity()};
      constraint_csv->row(integrator->t(), row);
    }
  };
  // The state at the last row written: where a stop message estimates how
  // stiff the model was (the state the run stopped at may be garbage).
  std::vector<double> last_row_y = y0;
  std::vector<double> state_peak(model.state_count(), 0.0);  // largest |state| over the rows
  double last_row_t = s.t_start_s;
  ProgressLine progress(hooks.progress && !linearize);
  std::unique_ptr<AnimationSink> animation;  // --animate: the writer run_main checked is installed
  if (!o.animate_path.empty() && animation_factory()) animation = animation_factory()(model);
  auto write_row = [&] {
    std::copy(integrator->y(), integrator->y() + n, last_row_y.begin());
    for (std::size_t i = 0; i < state_peak.size(); ++i)
      state_peak[i] = std::max(state_peak[i], std::abs(integrator->y()[i]));
    last_row_t = integrator->t();
    model.outputs(integrator->t(), integrator->y(), integrator->yp(), outputs.data());
    csv.row(integrator->t(), outputs);
    if (hooks.ranges) hooks.ranges->add(outputs);
    if (animation) animation->record(integrator->t(), integrator->y(), integrator->yp());
    observe_constraints();
    witness.observe(integrator->t(), integrator->y(), integrator->yp(), integrator->energy());
    if (penetrations.any()) penetrations.observe(integrator->t(), integrator->y(), witness.active() ? witness.absorbed() : NAN);
    if (progress.enabled() && s.t_end_s > s.t_start_s)
      progress.update((integrator->t() - s.t_start_s) / (s.t_end_s - s.t_start_s),
                      fmt::format("t = {} s of {} s", format_time(integrator->t()), format_time(s.t_end_s)));
  };

  const auto started = std::chrono::steady_clock::now();
  std::optional<Pacer> pacer;
  Outcome r;
  std::vector<Mode> modes;
  if (linearize) {
    r = march(guard, *integrator, s, y0, yp0, observe_constraints);
    if (model.is_dae()) {
      std::vector<double> a, b;
      if (r.ok) r.ok = numeric_pencil(guard, integrator->t(), integrator->y(), integrator->yp(), a, b);
      if (r.ok) modes = modes_of_pencil(a, b, n);
    } else {
      std::vector<double> jac;
      if (r.ok) r.ok = numeric_jacobian(guard, integrator->t(), integrator->y(), jac);
      if (r.ok) modes = modes_of(jac, n);
    }
    if (r.ok) write_modes(out, modes);
  } else if (o.realtime) {
    csv.header("t", columns);
    pacer.emplace(*o.realtime, s.t_start_s, OutputGrid(s.t_start_s, s.t_end_s, s.interval_s).size());
    r = march(guard, *integrator, s, y0, yp0, [&] {
      write_row();
      pacer->frame_done(integrator->t());
    }, hooks.stop);
  } else {
    csv.header("t", columns);
    r = march(guard, *integrator, s, y0, yp0, write_row, hooks.stop);
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  progress.clear();
  // the motion so far, also of a run that stopped early: it shows where
  if (animation) animation->write(o.animate_path);

  if (r.started)
    model.terminal(integrator->t(), integrator->y());
  else
    model.terminal(s.t_start_s, y0.data());

  // Why the run stopped (or crept), in model terms: the fastest mode against
  // an explicit method's stability limit; joint rows losing rank.
  bool penalty_joints = false;  // (a cut joint's rows are held, not springs)
  for (std::size_t r = 0; r < model.position_constraint_count(); ++r) penalty_joints = penalty_joints || !guard.row_held(r);
  std::string stop_note, stability;
  if (!model.is_dae() && !linearize) {
    const auto& blame = guard.blame();
    const bool blew_up = blame && blame->non_finite();
    if (!r.ok && r.started && (r.solver_failed || blew_up))
      stop_note = describe_stiffness(estimate_stiffness(model, last_row_t, last_row_y.data()), integrator->name(),
                                     !integrator_info(s.solver).adaptive ? (s.step_s > 0 ? s.step_s : s.interval_s / 10) : 0.0,
                                     penalty_joints);
    else if (r.ok)
      stability = stability_limited_note(model, *integrator, s.t_start_s, penalty_joints);
  }
  if (!r.ok && r.started) {
    // where the solver gave up (its last accepted state), else the last row
    const double* y_end = integrator->y();
    double t_end = integrator->t();
    if (!std::all_of(y_end, y_end + n, [](double v) { return std::isfinite(v); }))
      y_end = last_row_y.data(), t_end = last_row_t;
    const std::string rank = rank_loss_note(model, guard.constraint_shape(), s.t_start_s, y0.data(), t_end, y_end);
    if (!rank.empty()) stop_note += (stop_note.empty() ? "" : "; ") + rank;
  }

  if (!o.quiet) {
    RunRecord record;
    record.model = &model;
    record.integrator = integrator.get();
    record.settings = s;
    record.accuracy = o.accuracy_note;
    record.wall_s = wall_s;
    record.stability = stability;
    if (pacer) record.realtime = pacer->summary();
    record.small_states = describe_small_states(model, state_peak, s.atol);
    record.floored = describe_floored(model, integrator->floored_unknowns());
    if (witness.active()) {
      record.energy = witness.summary();
      record.energy_warning = witness.warning(s.rtol);
    }
    record.energy_note = model.energy_note();
    record.start_warnings = penetrations.summary();
    record.output = linearize ? fmt::format("{} modes to {}", modes.size(), out.display_name())
                              : fmt::format("{} rows to {}", csv.rows(), out.display_name());
    if (animation)
      record.output += fmt::format("; {} bod{} in {} frames to {}", animation->bodies(),
                                   animation->bodies() == 1 ? "y" : "ies", animation->frames(), o.animate_path);
    if (start.assembly) record.assembly = &*start.assembly;
    if (start.redundancy) record.redundancy = &*start.redundancy;
    if (start.initial_values) record.initial_values = &*start.initial_values;
    if (guard.constraint_shape().any()) record.constraints = &monitor;
    record.events = &guard.events();
    print_summary(hooks.report, record);
  }
  if (event_out) write_event_log(*event_out, guard.events());
  const std::string suspect = implicit_near_change_points(model, s.solver, integrator->steps_across());
  if (!suspect.empty()) o.strict ? print_error(suspect + " (--strict)") : print_warning(suspect);
  if (const std::string loosened = describe_loosenings(integrator->loosenings(), s); !loosened.empty())
    print_note(loosened);
  if (!r.ok) print_stop_message(hooks.report, guard, *integrator, r.solver_failed, stop_note);
  if (r.signal != 0) {  // said even with --quiet: the output is not the whole run
    fmt::print(hooks.report, "mbgrt: stopped by {} at t = {} s of {} s; the {} rows written are whole\n",
               signal_name(r.signal), format_time(last_row_t), format_time(s.t_end_s), csv.rows());
    return 128 + r.signal;
  }
  return r.ok && (suspect.empty() || !o.strict) ? kExitSuccess : kExitRunFailed;
}


}  // namespace mbgrt::detail
