// mbgc — the multibond-graph compiler. Command line only; the work is in
// driver::compile.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "codegen/emit_cpp.hpp"
#include "driver/driver.hpp"

int main(int argc, char** argv) {
  using mbgc::driver::Dump;
  CLI::App app{"mbgc " MBGC_VERSION " — compiles a multibond-graph model (.mbg) into a C++ simulator"};
  mbgc::driver::Options opt;
  std::string dump = "none", format = "text";
  app.add_option("model", opt.input, "the .mbg model file")->required();
  app.add_option("-o,--output", opt.output, "output file (default: standard output)");
  app.add_flag("--library", opt.library, "emit the model class without main(), to include in your own program");
  app.add_option("--namespace", opt.library_namespace,
                 "with --library: the C++ namespace of the model class (default mbgc_model), so that one program can "
                 "embed two builds of one model (a chain of 2 and of 32 rods)")
      ->check(mbgc::codegen::namespace_problem, "C++ identifier");
  app.add_option("--scene", opt.scene, "compile only what this scene's outputs need (scene NAME { outputs = [...] })");
  std::string explain;
  app.add_option("--explain-scene", explain,
                 "print what scene NAME keeps and removes (bodies, elements, signals, outputs) instead of C++");
  app.add_option("--outline", opt.outline,
                 "auto|always|never: bodies with the same equations computed by one function per shape, called per "
                 "body (auto: where the derivative written inline would outgrow the instruction cache, about "
                 "100,000 expression nodes; never: everything inline, to measure what outlining saves)")
      ->check(CLI::IsMember({"auto", "always", "never"}));
  app.add_flag("--time-passes", opt.time_passes, "print each pass's wall time on stderr (for mbgc's developers)");
  app.add_flag("--keep-unchanged", opt.keep_unchanged,
               "leave -o's file (and the depfile) untouched when its text would not change, so that Ninja's "
               "restat skips recompiling it (mbgc_add_simulation passes it under Ninja)");
  app.add_option("--depfile", opt.depfile, "also write a Makefile-style dependency file (model and imports)");
  app.add_option("--dump", dump, "print a compiler stage instead of C++")
      ->check(CLI::IsMember({"none", "ast", "expanded", "graph", "causality", "equations", "reduced"}));
  std::vector<std::string> sets;
  app.add_option("--set", sets, "NAME=VALUE: fix a top-level parameter at compile time (e.g. a chain's N)")
      ->allow_extra_args(false);
  std::string constraints;
  app.add_option("--constraints", constraints,
                 "auto|lagrange|penalty|coordinates: how joint constraints are enforced, replacing the model's "
                 "`constraints = ...` (a joint's own `constraint = ...` still wins; auto: coordinates, loops closed by cut joints, "
                 "where joint coordinates can move every joint, else lagrange)")
      ->check(CLI::IsMember({"auto", "lagrange", "penalty", "coordinates"}));
  std::string contacts;
  app.add_option("--contacts", contacts,
                 "unilateral|compliant: how contacts act, for every contact without its own `strategy = ...` "
                 "(default: unilateral)")
      ->check(CLI::IsMember({"unilateral", "compliant"}));
  app.add_option("-I,--include-dir", opt.search_dirs,
                 "a directory where modal-data files (flexible = modal(\"file.mbm\")) are looked for, after the model's own")
      ->allow_extra_args(false);
  app.add_option("--format", format, "dump format: text, or dot (Graphviz) for --dump=graph")
      ->check(CLI::IsMember({"text", "dot"}));
  std::string stats_format;
  app.add_flag("--stats", opt.stats,
               "print, instead of C++, one row per method of the generated model class: its lines, bytes and "
               "floating-point operations per call, as written (each binary + - * /, each unary minus not on a "
               "literal, each math function call incl. pow, fabs, fmin, fmax, each comparison of step/sign; x^2 "
               "and x^3 of a variable are x*x and x*x*x; a shared temporary counts once, where it is defined; "
               "mbgrt::solve_linear(n) counts (4n^3 + 9n^2 - 7n)/6; a body-shape function NAME_shapeK counts in NAME "
               "once per call, its lines and bytes once), then the totals and the whole file's lines and bytes");
  bool no_energy_witness = false;
  app.add_flag("--no-energy-witness", no_energy_witness,
               "leave out the energy balance (stored_energy() and power(), whose code can reach the "
               "dynamics' own size): the simulator then reports no energy residual");
  bool no_rotors = false;
  app.add_flag("--no-rotors", no_rotors,
               "write every body's equations in its own frame, also a rotor's (a body symmetric about the "
               "revolute joint it spins on, whose frame otherwise leaves out its spin): the same motion, more "
               "operations, to compare the two forms");
  std::string units = "check";
  app.add_option("--units", units,
                 "the units of measure: check (the default: equations whose units disagree are errors), strict "
                 "(also every parameter's unit declared or inferred), report (print every parameter's and "
                 "output's unit instead of C++), off")
      ->check(CLI::IsMember({"check", "strict", "report", "off"}));
  app.add_option("--stats-format", stats_format, "with --stats: text (a table, the default) or csv")
      ->check(CLI::IsMember({"text", "csv"}));
  app.add_option("--fmu", opt.fmu,
                 "build a Functional Mock-up Unit (FMI) of the model into this file instead of writing C++ "
                 "(docs/fmi.md)");
  int fmi = 3;
  app.add_option("--fmi", fmi, "with --fmu: the FMI version, 3 (the default) or 2")->check(CLI::IsMember({3, 2}));
  std::string fmu_kind = "both";
  app.add_option("--fmu-kind", fmu_kind, "with --fmu: model exchange (me), co-simulation (cs) or both (the default)")
      ->check(CLI::IsMember({"me", "cs", "both"}));
  app.set_version_flag("--version", "mbgc " MBGC_VERSION);
  CLI11_PARSE(app, argc, argv);
  opt.units = units == "strict"   ? mbgc::driver::Options::Units::Strict
              : units == "report" ? mbgc::driver::Options::Units::Report
              : units == "off"    ? mbgc::driver::Options::Units::Off
                                  : mbgc::driver::Options::Units::Check;
  if (!explain.empty()) {
    if (!opt.scene.empty() && opt.scene != explain) {
      std::cerr << "mbgc: error: --scene " << opt.scene << " and --explain-scene " << explain << " name different scenes\n";
      return 2;
    }
    opt.scene = explain;
    opt.explain_scene = true;
  }
  for (const std::string& s : sets) {
    auto eq = s.find('=');
    char* end = nullptr;
    double v = eq == std::string::npos ? 0.0 : std::strtod(s.c_str() + eq + 1, &end);
    if (eq == std::string::npos || eq == 0 || end == s.c_str() + eq + 1 || *end != '\0') {
      std::cerr << "mbgc: error: --set expects NAME=NUMBER, got `" << s << "`\n";
      return 2;
    }
    if (!std::isfinite(v)) {
      std::cerr << "mbgc: error: --set " << s.substr(0, eq) << ": `" << s.substr(eq + 1)
                << "` is not a finite number (the largest double is about 1.8e308)\n";
      return 2;
    }
    opt.overrides[s.substr(0, eq)] = v;
  }
  if (constraints == "auto") opt.constraints = mbgc::multibody::Strategy::Auto;
  if (constraints == "coordinates") opt.constraints = mbgc::multibody::Strategy::Coordinates;
  if (constraints == "lagrange") opt.constraints = mbgc::multibody::Strategy::Lagrange;
  if (constraints == "penalty") opt.constraints = mbgc::multibody::Strategy::Penalty;
  if (contacts == "unilateral") opt.contacts = mbgc::multibody::ContactStrategy::Unilateral;
  if (contacts == "compliant") opt.contacts = mbgc::multibody::ContactStrategy::Compliant;
  static const std::map<std::string, Dump> dumps = {{"none", Dump::None},           {"ast", Dump::Ast}, {"expanded", Dump::Expanded},
                                                    {"graph", Dump::Graph},         {"causality", Dump::Causality},
                                                    {"equations", Dump::Equations}, {"reduced", Dump::Reduced}};
  opt.dump = dumps.at(dump);
  opt.dot = format == "dot";
  if (opt.dot && opt.dump != Dump::Graph) {
    std::cerr << "mbgc: error: --format=dot goes with --dump=graph\n";
    return 2;
  }
  if (!stats_format.empty() && !opt.stats) {
    std::cerr << "mbgc: error: --stats-format goes with --stats\n";
    return 2;
  }
  opt.stats_csv = stats_format == "csv";
  opt.energy_witness = !no_energy_witness;
  opt.rotors = !no_rotors;
  if (opt.stats && (opt.dump != Dump::None || opt.explain_scene)) {
    std::cerr << "mbgc: error: --stats prints the generated code's costs: it does not go with --dump or --explain-scene\n";
    return 2;
  }
  const bool fmu_options = app.count("--fmi") > 0 || app.count("--fmu-kind") > 0;
  if (fmu_options && opt.fmu.empty()) {
    std::cerr << "mbgc: error: --fmi and --fmu-kind go with --fmu FILE\n";
    return 2;
  }
  if (!opt.fmu.empty() && (opt.dump != Dump::None || opt.stats || opt.explain_scene || opt.library)) {
    std::cerr << "mbgc: error: --fmu builds an FMU: it does not go with --dump, --stats, --explain-scene or --library\n";
    return 2;
  }
  opt.fmi_version = fmi;
  opt.fmu_model_exchange = fmu_kind != "cs";
  opt.fmu_co_simulation = fmu_kind != "me";
  opt.exit_when_done = true;
  try {
    return mbgc::driver::compile(opt, std::cout, std::cerr);
  } catch (const mbgc::ir::InternalError& e) {
    std::cerr << "mbgc: internal error: " << e.what() << "\n(a bug in mbgc, not in the model: please report it with the model)\n";
    return 70;
  }
}
