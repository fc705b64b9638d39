// driver/driver.hpp — the only place that knows the order of the passes:
//
//   parse -> unroll loops -> expand multibody -> resolve -> graph -> causality
//         -> equations -> reduce -> emit
//
// Each pass reports into one Diagnostics; the pipeline stops after the first
// pass with an error, so later passes only ever see well-formed input.
#pragma once

#include <map>
#include <optional>
#include <ostream>
#include <string>

#include "ir/limits.hpp"
#include "multibody/expand.hpp"

namespace mbgc::driver {

enum class Dump { None, Ast, Expanded, Graph, Causality, Equations, Reduced };

struct Options {
  std::string input;          ///< the .mbg file
  std::string output;         ///< -o file ("" or "-": stdout)
  Dump dump = Dump::None;
  bool dot = false;           ///< --format=dot (graph and causality dumps)
  bool library = false;       ///< --library: model class without main()
  std::string library_namespace = "mbgc_model";  ///< --namespace: where --library puts the class
  std::string scene;          ///< --scene: compile only what this scene's outputs need
  bool explain_scene = false;  ///< --explain-scene: print what the scene removes instead of C++
  std::string outline = "auto";  ///< --outline auto|always|never (codegen/outline.hpp)
  bool time_passes = false;   ///< --time-passes: each pass's wall time on stderr
  bool exit_when_done = false;  ///< end the process once the C++ is written, without freeing (the executable's main)
  bool keep_unchanged = false;  ///< --keep-unchanged: do not rewrite an output whose text is the same
  std::string depfile;        ///< --depfile: Makefile-style list of the files read (for build tools)
  std::map<std::string, double> overrides;  ///< --set NAME=VALUE: top-level parameters fixed at compile time
  std::vector<std::string> search_dirs;              ///< -I: where modal-data files are looked for
  std::optional<multibody::Strategy> constraints;  ///< --constraints: replaces the model's `constraints = ...`
  std::optional<multibody::ContactStrategy> contacts;  ///< --contacts: of every contact without its own `strategy`
  bool stats = false;         ///< --stats: print each generated method's operations and size instead of C++
  bool stats_csv = false;     ///< --stats-format=csv
  /// --units: check (contradictions are errors), strict (and every parameter's unit
  /// known), report (print every parameter's and output's unit instead of C++), off
  enum class Units { Check, Strict, Report, Off } units = Units::Check;
  bool energy_witness = true;  ///< false: --no-energy-witness (no stored_energy() or power(): reduce/energy.hpp)
  bool rotors = true;          ///< false: --no-rotors (every body in its own frame: multibody/rotors.hpp)
  std::string fmu;             ///< --fmu FILE: build a Functional Mock-up Unit there instead of writing C++
  int fmi_version = 3;         ///< --fmi 3|2
  bool fmu_model_exchange = true, fmu_co_simulation = true;  ///< --fmu-kind me|cs|both
  ir::Limits limits;          ///< how large a model may grow (the fuzz targets lower them)
};

/// Runs the compiler. Returns the exit status: 0 ok, 1 errors in the model,
/// 3 the output file could not be written. Diagnostics go to `err`.
/// The output file is written only when everything succeeded (never partially).
int compile(const Options& options, std::ostream& out, std::ostream& err);

}  // namespace mbgc::driver
