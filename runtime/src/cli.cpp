#include "cli.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "integrator.hpp"

namespace mbgrt::detail {

namespace {

/// Thrown for option values CLI11 accepts syntactically but we do not.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double parse_number(const std::string& text, const std::string& what) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value))
    throw UsageError(fmt::format("{}: '{}' is not a finite number", what, text));
  return value;
}

std::pair<std::string, double> parse_override(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError(fmt::format("--set '{}': expected NAME=VALUE", arg));
  std::string name = arg.substr(0, eq);
  return {name, parse_number(arg.substr(eq + 1), fmt::format("--set {}", name))};
}

std::string fixed_step_names() {
  return integrator_names_where([](const IntegratorInfo& i) { return !i.adaptive; });
}
std::string linear_solver_names() {
  return integrator_names_where([](const IntegratorInfo& i) { return i.linear_solver; });
}

/// --solver's help: each integrator and what it is.
std::string solver_help() {
  std::string s = "Integrator:";
  for (const IntegratorInfo& i : kIntegrators) s += fmt::format(" {} ({});", i.name, i.method);
  s.back() = '.';
  return s;
}

Solver solver_from_name(const std::string& name) {
  if (const IntegratorInfo* i = find_integrator(name)) return i->solver;
  throw UsageError(fmt::format("--solver: unknown solver '{}' (use {})", name, integrator_names()));
}

LinearSolver linear_solver_from_name(const std::string& name) {
  if (name == "auto") return LinearSolver::automatic;
  if (name == "dense") return LinearSolver::dense;
  if (name == "sparse") return LinearSolver::sparse;
  throw UsageError(fmt::format("--linear-solver: unknown '{}' (use auto, dense or sparse)", name));
}

void require(bool ok, const std::string& message) {
  if (!ok) throw UsageError(message);
}

/// NAME=FROM:TO:COUNT
SweepAxis parse_sweep(const std::string& arg) {
  const auto eq = arg.find('=');
  const auto c1 = arg.find(':', eq == std::string::npos ? 0 : eq);
  const auto c2 = c1 == std::string::npos ? c1 : arg.find(':', c1 + 1);
  if (eq == std::string::npos || eq == 0 || c1 == std::string::npos || c2 == std::string::npos ||
      arg.find(':', c2 + 1) != std::string::npos)
    throw UsageError(fmt::format("--sweep '{}': expected NAME=FROM:TO:COUNT (e.g. k=100:1000:10)", arg));
  SweepAxis axis;
  axis.name = arg.substr(0, eq);
  const std::string what = fmt::format("--sweep {}", axis.name);
  axis.from = parse_number(arg.substr(eq + 1, c1 - eq - 1), what + " FROM");
  axis.to = parse_number(arg.substr(c1 + 1, c2 - c1 - 1), what + " TO");
  const std::string count = arg.substr(c2 + 1);
  auto [ptr, ec] = std::from_chars(count.data(), count.data() + count.size(), axis.count);
  require(ec == std::errc() && ptr == count.data() + count.size() && axis.count >= 1 && axis.count <= kMaxSweepCases,
          fmt::format("{} COUNT: '{}' is not a whole number from 1 to {}", what, count, kMaxSweepCases));
  require(axis.count > 1 || axis.from == axis.to,
          fmt::format("{}: COUNT 1 takes one value, but FROM {} and TO {} differ", what, axis.from, axis.to));
  return axis;
}

void validate(const Options& o, bool step_given) {
  const Settings& s = o.settings;
  require(std::isfinite(s.t_end_s) && s.t_end_s >= s.t_start_s,
          fmt::format("--t-end {} is before the start time {} s", s.t_end_s, s.t_start_s));
  require(std::isfinite(s.interval_s) && s.interval_s > 0,
          fmt::format("--interval must be positive (got {})", s.interval_s));
  require(std::isfinite(s.rtol) && s.rtol >= 0,
          fmt::format("--rtol must be >= 0 (got {})", s.rtol));
  require(std::isfinite(s.atol) && s.atol >= 0,
          fmt::format("--atol must be >= 0 (got {})", s.atol));
  require(s.rtol > 0 || s.atol > 0, "--rtol and --atol cannot both be zero");
  require(std::isfinite(s.step_s) && s.step_s >= 0,
          fmt::format("--step must be positive (got {})", s.step_s));
  if (step_given) {
    // Silently ignoring --step would make a work-precision study measure
    // something other than what its author asked for.
    require(!integrator_info(s.solver).adaptive,
            fmt::format("--step applies only to a fixed-step solver ({}), not to {}", fixed_step_names(),
                        solver_name(s.solver)));
    require(s.step_s > 0, "--step must be positive");
  }
  require(!(o.linearize_at && o.work_precision),
          "--linearize-at and --work-precision are two different runs: give one of them");
  if (o.realtime) {
    require(std::isfinite(*o.realtime) && *o.realtime > 0,
            fmt::format("--realtime {}: the factor must be a positive number (1: real time)", *o.realtime));
    require(!o.linearize_at && !o.work_precision, "--realtime paces a simulation run, not --linearize-at or --work-precision");
  }
  if (o.sweeping()) {
    require(o.sweep.empty() || o.sweep_file.empty(), "--sweep and --sweep-file are two ways to give the cases: use one");
    require(!o.linearize_at && !o.work_precision && !o.realtime,
            "a sweep runs simulations: not with --linearize-at, --work-precision or --realtime");
    require(o.constraint_report_path.empty() && o.event_log_path.empty() && o.animate_path.empty(),
            "--constraint-report, --event-log and --animate are for one run; a sweep's per-case files go to --case-dir");
    double cases = 1;
    for (std::size_t i = 0; i < o.sweep.size(); ++i) {
      cases *= static_cast<double>(o.sweep[i].count);
      for (std::size_t j = 0; j < i; ++j)
        require(o.sweep[j].name != o.sweep[i].name, fmt::format("--sweep {}: given twice", o.sweep[i].name));
    }
    require(cases <= static_cast<double>(kMaxSweepCases),
            fmt::format("--sweep: the grid has {:.0f} cases, more than the {} a sweep may run", cases, kMaxSweepCases));
  } else {
    require(o.case_dir.empty(), "--case-dir applies to a sweep (--sweep or --sweep-file)");
  }
  require(o.animate_path.empty() || (!o.linearize_at && !o.work_precision),
          "--animate records a simulation run, not --linearize-at or --work-precision");
  if (o.linearize_at)
    require(std::isfinite(*o.linearize_at) && *o.linearize_at >= s.t_start_s,
            fmt::format("--linearize-at {} is before the start time {} s", *o.linearize_at,
                        s.t_start_s));
}

}  // namespace

ParseOutcome parse_command_line(const Model& model, int argc, char** argv) {
  Options o;
  o.settings = model.default_settings();
  Settings& s = o.settings;

  CLI::App app{fmt::format("Simulator for model '{}', generated by mbgc from {}.", model.name(),
                           model.source_file())};
  app.footer(
      "Exit status: 0 success, 1 solver failure or divergence (rows already written are kept), "
      "2 bad command line.\n");

  std::string solver = solver_name(s.solver);
  std::string linear_solver = "auto";
  std::vector<std::string> sets, sweeps;
  double linearize_at = 0.0;
  std::string realtime;  // empty when --realtime is given without a factor

  app.add_option("--t-end", s.t_end_s, "Stop time [s]")
      ->type_name("SECONDS")
      ->capture_default_str();
  app.add_option("--interval", s.interval_s, "Communication interval: one CSV row each [s]")
      ->type_name("SECONDS")
      ->capture_default_str();
  auto* solver_option = app.add_option("--solver", solver, solver_help())
      ->type_name("NAME")
      ->capture_default_str();
  auto* rtol = app.add_option("--rtol", s.rtol, "Relative tolerance (adaptive solvers)")
      ->type_name("X")
      ->capture_default_str();
  auto* atol = app.add_option("--atol", s.atol, "Absolute tolerance (adaptive solvers)")
      ->type_name("X")
      ->capture_default_str();
  auto* linear = app.add_option("--linear-solver", linear_solver,
                                fmt::format("The linear solver of {}: dense (LU), sparse (KLU on the model's sparsity "
                                            "pattern, columns differenced in groups) or auto (sparse for a DAE of {} "
                                            "unknowns or more)",
                                            linear_solver_names(), kSparseFromUnknowns))
                     ->type_name("NAME")
                     ->capture_default_str();
  auto* step = app.add_option("--step", s.step_s,
                              fmt::format("Fixed step for {} [s] (default: interval/10)", fixed_step_names()))
                   ->type_name("SECONDS");
  auto* accuracy = app.add_option("--accuracy", s.accuracy,
                                  "Pick the solver and its step or tolerance for this run: the cheapest that keeps the "
                                  "outputs' relative error within X, measured by trial runs of the whole run against a "
                                  "tighter reference")
                       ->type_name("X");
  auto* rho = app.add_option("--rho-inf", s.rho_inf,
                             "generalized_alpha: the spectral radius at an infinite step, from 0 (modes far above "
                             "1/step damped out in one step) to 1 (none damped)")
                  ->type_name("X")
                  ->capture_default_str();
  app.add_option("--set", sets, "Override a parameter (repeatable)")
      ->type_name("NAME=VALUE")
      ->allow_extra_args(false);
  app.add_option("-o,--out", o.out_path, "CSV output file (default: stdout)")
      ->type_name("FILE.csv");
  app.add_option("--constraint-report", o.constraint_report_path,
                 "Write t,max_abs_g,max_abs_gdot (joint constraints at each output time) as CSV")
      ->type_name("FILE.csv");
  app.add_option("--event-log", o.event_log_path,
                 "Write t,event,name,state,jump,note (every switch of the model's events; note: what a contact did) as CSV")
      ->type_name("FILE.csv");
  app.add_option("--animate", o.animate_path,
                 "Write the motion of every body as binary glTF 2.0 (a node per body, keyframed at the rows; a "
                 "flexible body's modes as morph targets), for any glTF viewer")
      ->type_name("FILE.glb");
  app.add_flag("--quiet", o.quiet, "Do not print the run summary or the progress line on stderr");
  app.add_flag("--list-parameters", o.list_parameters,
               "Print the parameters as NAME,DEFAULT lines and exit");
  auto* lin = app.add_option("--linearize-at", linearize_at,
                             "Integrate to this time [s], then write the eigenvalues of the "
                             "Jacobian as CSV (index,omega_rad_s,f_hz,damping_ratio)")
                  ->type_name("SECONDS");
  auto* paced = app.add_option("--realtime", realtime,
                               "Pace the rows to the wall clock, FACTOR times faster than real time (default 1); "
                               "report points computed after their moment (overruns) and the median and worst "
                               "compute time per frame")
                    ->type_name("[FACTOR]")
                    ->expected(0, 1);
  app.add_flag("--fd-jacobian", o.fd_jacobian,
               "Implicit solvers: use finite-difference Jacobians even where the model generates one "
               "(to measure what the generated Jacobian saves)");
  app.add_flag("--strict", o.strict,
               "Make the warnings about a suspect run errors with exit status 1: a start inside a unilateral "
               "contact's surface (nothing is integrated), an implicit method carried across a change point of the "
               "cut joints");
  app.add_flag("--no-energy-witness", o.no_energy_witness,
               "Do not integrate the model's energy balance beside the state (the summary's `energy` line, an "
               "error estimate that needs no reference run: it costs one evaluation of the model's power per "
               "step, per stage for rk4 and dopri5); --realtime leaves it out too");
  app.add_flag("--work-precision", o.work_precision,
               "Run every integrator that fits the model over a range of tolerances (rk4: "
               "steps) and write CSV of cost against error (solver,rtol,atol,step_s,wall_s,"
               "steps,rhs_evals,fd_jac_rhs_evals,jac_evals,max_rel_error,energy_residual,status); the error "
               "is against a reference run at rtol 1e-12");

  app.add_option("--sweep", sweeps,
                 "Run one case per value of parameter NAME, COUNT values from FROM to TO (repeatable: the grid of "
                 "every combination, the first varying slowest); --out is then the summary CSV, one row per case")
      ->type_name("NAME=FROM:TO:COUNT")
      ->allow_extra_args(false);
  app.add_option("--sweep-file", o.sweep_file,
                 "Run one case per row of a CSV file whose header names the parameters it sets")
      ->type_name("FILE.csv");
  app.add_option("--case-dir", o.case_dir,
                 "With a sweep: write each case's CSV and run report to DIR/case_0001.csv, .log, ...")
      ->type_name("DIR");
  auto* jobs = app.add_option("--jobs", o.jobs, "With a sweep: cases run at once (default: one per core)")
                   ->type_name("N");

  try {
    app.parse(argc, argv);
    for (const std::string& arg : sweeps) o.sweep.push_back(parse_sweep(arg));
    require(jobs->count() == 0 || o.jobs >= 1, "--jobs must be at least 1");
    require(jobs->count() == 0 || !o.sweep.empty() || !o.sweep_file.empty(), "--jobs applies to a sweep (--sweep or --sweep-file)");
    s.solver = solver_from_name(solver);
    s.linear_solver = linear_solver_from_name(linear_solver);
    for (const std::string& arg : sets) o.overrides.push_back(parse_override(arg));
    if (lin->count() > 0) o.linearize_at = linearize_at;
    if (paced->count() > 0) {
      o.realtime = 1.0;
      if (!realtime.empty()) {
        std::size_t used = 0;
        try {
          o.realtime = std::stod(realtime, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        require(used == realtime.size() && used > 0,
                fmt::format("--realtime {}: the factor is a number (1: real time, 10: ten times faster)", realtime));
      }
    }
    // --accuracy chooses the solver: one given beside it (or --step, --rtol, --atol) would not be used, and a
    // solver given on its own overrides the model's `simulate { accuracy = ... }`
    const std::size_t chosen_by_hand = solver_option->count() + step->count() + rtol->count() + atol->count();
    if (accuracy->count() > 0) {
      require(chosen_by_hand == 0 && rho->count() == 0,
              "--accuracy chooses the solver and its step or tolerances: give --accuracy or those, not both");
      require(std::isfinite(s.accuracy) && s.accuracy > 0,
              fmt::format("--accuracy must be a positive relative error (got {})", s.accuracy));
      require(!lin->count() && !o.work_precision && o.sweep.empty() && o.sweep_file.empty(),
              "--accuracy picks the solver of one run: not with --linearize-at, --work-precision or a sweep");
    } else if (chosen_by_hand > 0) {
      s.accuracy = 0.0;
    }
    validate(o, step->count() > 0);
    require(rho->count() == 0 || s.solver == Solver::generalized_alpha,
            fmt::format("--rho-inf applies to --solver generalized_alpha only, not to {}", solver_name(s.solver)));
    require(std::isfinite(s.rho_inf) && s.rho_inf >= 0 && s.rho_inf <= 1,
            fmt::format("--rho-inf must be from 0 to 1 (got {})", s.rho_inf));
    // (like --step: a linear solver asked for and silently not used would
    // make a comparison measure something else than its author meant)
    if (linear->count() > 0 && s.linear_solver != LinearSolver::automatic)
      require(integrator_info(s.solver).linear_solver,
              fmt::format("--linear-solver applies to --solver {} only", linear_solver_names()));
    if (s.linear_solver == LinearSolver::sparse) {
      std::vector<long> starts, rows;
      require(model.is_dae() && model.residual_sparsity(starts, rows),
              fmt::format("--linear-solver sparse: model '{}' gives no sparsity pattern (mbgc gives one for DAE "
                          "models only)",
                          model.name()));
    }
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help
      app.exit(e);
      return {std::nullopt, kExitSuccess};
    }
    print_error(fmt::format("{}\nRun with --help for the list of options.", e.what()));
    return {std::nullopt, kExitUsage};
  } catch (const UsageError& e) {
    print_error(e.what());
    return {std::nullopt, kExitUsage};
  }
  return {std::move(o), kExitSuccess};
}

}  // namespace mbgrt::detail
