// run_main: command line -> parameters -> the run (simulate.cpp), a
// work-precision study or a sweep -> CSV, summary, stop message. The order
// of events here is the behaviour docs/cli.md promises.
#include <fmt/format.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>

#include "accuracy.hpp"
#include "animation_sink.hpp"
#include "cli.hpp"
#include "csv.hpp"
#include "interrupt.hpp"
#include "mbgrt/model.hpp"
#include "progress.hpp"
#include "simulate.hpp"
#include "sweep.hpp"
#include "work_precision.hpp"

namespace mbgrt {

namespace detail {

namespace {

/// NAME,DEFAULT,UNIT lines: the unit a parameter is declared in (`--set`
/// reads it in that unit), else its SI unit where the compiler found it, else
/// none (NAME,DEFAULT). A parameter computed from others (a body's r0 from
/// its joint, say) has no default of its own: `(computed: FORMULA)`, not `nan`.
int list_parameters(const Model& model) {
  for (const ParameterInfo& p : model.parameters()) {
    const bool computed = std::isnan(p.default_value);
    const std::string& unit = !computed && !p.unit_or_doc.empty() ? p.unit_or_doc : p.si_unit;
    const std::string tail = unit.empty() ? "" : "," + unit;
    if (!computed) {
      fmt::print(stdout, "{},{}{}\n", p.name, p.default_value, tail);
      continue;
    }
    std::string formula = p.unit_or_doc.rfind("= ", 0) == 0 ? p.unit_or_doc.substr(2) : p.unit_or_doc;
    fmt::print(stdout, "{},(computed{}{}){}\n", p.name, formula.empty() ? "" : ": ", formula, tail);
  }
  std::fflush(stdout);
  return kExitSuccess;
}

int run(Model& model, int argc, char** argv) {
  ParseOutcome parsed = parse_command_line(model, argc, argv);
  if (!parsed.options) return parsed.exit_status;
  const Options& o = *parsed.options;

  if (o.list_parameters) return list_parameters(model);
  if (!apply_overrides(model, o) || !check_model_fits(model, o)) return kExitUsage;
  if (!o.animate_path.empty() && model.body_count() == 0) {
    print_error(fmt::format("--animate: model '{}' describes no bodies to draw (a bond graph has none)", model.name()));
    return kExitUsage;
  }
  if (!o.animate_path.empty() && !animation_factory()) {
    print_error("--animate: this program was built without the glTF writer; it calls "
                "mbgrt::use_gltf_animation() to have it (mbgrt/features.hpp)");
    return kExitUsage;
  }

  // --accuracy (or the model's simulate { accuracy }): a probe picks a single
  // run's solver before anything is written
  Options chosen;
  if (o.settings.accuracy > 0 && !o.linearize_at && !o.work_precision && !o.sweeping()) {
    std::optional<AccuracyChoice> choice = choose_for_accuracy(model, o.settings, o.settings.accuracy);
    if (!choice) return kExitRunFailed;
    chosen = o;
    chosen.settings = choice->settings;
    chosen.accuracy_note = std::move(choice->note);
  }
  const Options& run_options = chosen.accuracy_note.empty() ? o : chosen;

  // A single run's files are written by a writer process that keeps their
  // rows whole even if the simulator is killed (csv.hpp); a sweep's threads
  // and MPI's ranks rule out forking, and their own records say what finished.
  const bool single = !o.work_precision && !o.sweeping();
  const auto rows = single ? OutputFile::Rows::Whole : OutputFile::Rows::AsWritten;
  std::optional<OutputFile> out, constraint_out, event_out;
  try {
    out.emplace(o.out_path, rows);
    if (!o.constraint_report_path.empty()) constraint_out.emplace(o.constraint_report_path, rows);
    if (!o.event_log_path.empty()) event_out.emplace(o.event_log_path, rows);
  } catch (const std::runtime_error& e) {
    print_error(e.what());
    return kExitUsage;
  }
  if (o.work_precision) return work_precision(model, o, *out);
  if (o.sweeping()) return run_sweep(model, o, *out);
  RunHooks hooks;
  hooks.progress = is_terminal(stderr) && !o.quiet;
  const StopSignals stop_signals({SIGINT, SIGTERM, SIGHUP});  // a run asked to stop ends after a whole row
  hooks.stop = &StopSignals::flag();
  const int status = simulate(model, run_options, *out, constraint_out ? &*constraint_out : nullptr,
                              event_out ? &*event_out : nullptr, hooks);
  for (auto* file : {&event_out, &constraint_out, &out})
    if (*file) (*file)->close();  // throws if a writer could not write it all
  return status;
}

}  // namespace

}  // namespace detail

int run_main(Model& model, int argc, char** argv) {
  try {
    return detail::run(model, argc, argv);
  } catch (const std::exception& e) {
    detail::print_error(e.what());
  } catch (...) {
    detail::print_error("unknown internal error");
  }
  return detail::kExitRunFailed;
}

}  // namespace mbgrt
