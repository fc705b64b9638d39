#include "driver/driver.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "causality/scap.hpp"
#include "codegen/emit_cpp.hpp"
#include "elaborate/unroll.hpp"
#include "fmu/interface.hpp"
#include "fmu/model_description.hpp"
#include "fmu/package.hpp"
#include "fmu/sources.hpp"
#include "multibody/expand.hpp"
#include "equations/generate.hpp"
#include "graph/build_graph.hpp"
#include "ir/print.hpp"
#include "parse/parse.hpp"
#include "reduce/reduce.hpp"
#include "scene/scene.hpp"
#include "sema/resolve.hpp"
#include "units/check.hpp"

#include <unistd.h>  // getpid

namespace mbgc::driver {
namespace {

/// Writes `text` to `path` through a temporary file and a rename, so a failed
/// write never leaves a partial file. With `keep_unchanged`
/// an existing file with the same text is left untouched: a build system
/// that checks outputs after a command (Ninja's restat, which CMake sets for
/// custom commands) then skips recompiling a simulator when a new mbgc
/// generates the same C++. A path that is not a regular file (`-o
/// /dev/null`, a pipe) is written in place: renaming over it would replace
/// the device with a file. The temporary's name carries the process id, so
/// that two compilations writing the same path never share one.
bool write_atomically(const std::string& given, const std::string& text, bool keep_unchanged) {
  namespace fs = std::filesystem;
  std::error_code status_error;
  if (const auto st = fs::status(given, status_error); !status_error && fs::exists(st) && !fs::is_regular_file(st)) {
    std::ofstream f(given, std::ios::binary);
    return f && (f << text) && f.flush();
  }
  // a symbolic link keeps pointing where it did: its target is replaced
  std::string path = given;
  std::error_code link_error;
  if (fs::is_symlink(fs::symlink_status(given, link_error)) && !link_error)
    if (fs::path target = fs::weakly_canonical(given, link_error); !link_error) path = target.string();
  if (keep_unchanged) {
    std::ifstream existing(path, std::ios::binary);
    if (existing) {
      const std::string old((std::istreambuf_iterator<char>(existing)), std::istreambuf_iterator<char>());
      if (old == text) return true;
    }
  }
  const std::string tmp = path + ".mbgc-tmp-" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) return false;
    f << text;
    if (!f.flush()) {
      std::remove(tmp.c_str());
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) std::remove(tmp.c_str());
  return !ec;
}

/// --depfile: `target` and the files the compilation read (the model and its
/// imports), for build tools; false (and an error said) if it cannot be written.
bool write_depfile(const Options& opt, const std::string& target, const ir::SourceManager& sources, std::ostream& err) {
  if (opt.depfile.empty()) return true;
  std::string deps = target + ":";
  for (int f = 0; f < sources.count(); ++f) deps += " " + sources.file(f).display_path;
  if (write_atomically(opt.depfile, deps + "\n", opt.keep_unchanged)) return true;
  err << "mbgc: error: cannot write `" << opt.depfile << "`\n";
  return false;
}

/// mbgc --fmu: the model's FMU (fmu/package.hpp), or why not.
int export_fmu(const Options& opt, const ir::ReducedSystem& reduced, const ir::SourceManager& sources,
               codegen::EmitOptions emit, std::ostream& err) {
  if (reduced.dae) {
    err << "mbgc: error: model `" << reduced.graph.model_name
        << "` is a DAE (its joints are held by Lagrange multipliers, or its equations have algebraic unknowns): an "
           "FMU exports an ODE\n"
        << "  hint: export it in joint coordinates or with penalty joints (mbgc --fmu ... --constraints coordinates)\n";
    return 1;
  }
  const fmu::Interface interface = fmu::describe(reduced, sources);
  emit.entry_point = [&interface](const std::string& class_name) { return fmu::entry_source(interface, class_name); };
  std::string source = codegen::emit_cpp(reduced, sources, emit);
  const std::string token = fmu::token_of(source);
  source.replace(source.find(fmu::kTokenPlaceholder), std::string(fmu::kTokenPlaceholder).size(), token);
  const fmu::FmiVersion version = opt.fmi_version == 2 ? fmu::FmiVersion::v2 : fmu::FmiVersion::v3;
  fmu::Package package;
  package.model_identifier = reduced.graph.model_name;
  package.source = source;
  package.version = version;
  package.model_description = fmu::model_description(interface, version, {opt.fmu_model_exchange, opt.fmu_co_simulation},
                                                     token, std::string("mbgc ") + MBGC_VERSION,
                                                     fmu::compiled_sources(package.model_identifier));
  if (const std::string error = fmu::write_fmu(package, opt.fmu); !error.empty()) {
    err << "mbgc: error: " << error << "\n";
    return 3;
  }
  if (!write_depfile(opt, opt.fmu, sources, err)) return 3;
  return 0;
}

}  // namespace

int compile(const Options& opt, std::ostream& out, std::ostream& err) {
  ir::SourceManager sources;
  ir::Diagnostics diags(sources);
  auto failed = [&]() {
    if (!diags.has_errors()) return false;
    diags.render(err);
    err << diags.error_count() << (diags.error_count() == 1 ? " error" : " errors") << " generated.\n";
    return true;
  };
  auto finish = [&](const std::string& text) {
    diags.render(err);  // warnings, if any
    if (opt.output.empty() || opt.output == "-") {
      out << text;
      return 0;
    }
    if (!write_atomically(opt.output, text, opt.keep_unchanged)) {
      err << "mbgc: error: cannot write `" << opt.output << "`\n";
      return 3;
    }
    if (!write_depfile(opt, opt.output, sources, err)) return 3;
    return 0;
  };

  // --time-passes: each pass's wall time, on stderr.
  auto last = std::chrono::steady_clock::now();
  auto timed = [&](const char* pass) {
    if (!opt.time_passes) return;
    const auto now = std::chrono::steady_clock::now();
    err << fmt::format("mbgc: {:<10} {:.3f} s\n", pass, std::chrono::duration<double>(now - last).count());
    last = now;
  };
  ir::AstProgram ast = parse::load_program(opt.input, sources, diags);
  timed("parse");
  if (failed()) return 1;
  if (opt.dump == Dump::Ast) return finish(ir::print_ast(ast));

  // Scenes leave the program here; the chosen one fixes parameters like --set
  // (an explicit --set still wins) and prunes the graph below.
  const std::vector<ir::AstScene> scenes = scene::take_scenes(ast, diags);
  if (failed()) return 1;
  std::optional<scene::SelectedScene> selected;
  std::map<std::string, double> overrides = opt.overrides;
  if (!opt.scene.empty()) {
    selected = scene::select_scene(scenes, opt.scene, ast, diags);
    if (failed()) return 1;
    if (!selected) {
      err << "mbgc: error: " << scene::no_such_scene(scenes, opt.scene) << "\n";
      return 1;
    }
    for (const auto& [name, value] : selected->overrides) overrides.emplace(name, value);
  }

  ast = elaborate::unroll_loops(ast, overrides, diags, opt.limits);
  timed("unroll");
  if (failed()) return 1;
  std::string strategy_report;  // what constraints = auto chose, for the causality report
  ir::ExpandedProgram expanded =
      multibody::expand(ast, sources, diags, {opt.constraints, opt.search_dirs, opt.contacts, &strategy_report, opt.rotors});
  timed("expand");
  if (failed()) return 1;
  if (opt.dump == Dump::Expanded) return finish(ir::print_expanded(expanded));

  ir::ResolvedModel resolved = sema::resolve(expanded, opt.input, diags, opt.limits);
  timed("resolve");
  if (failed()) return 1;
  ir::BondGraph graph = graph::build_graph(resolved, sources, diags);
  timed("graph");
  if (failed()) return 1;
  if (opt.constraints) graph.settings.form_option = "--constraints " + std::string(multibody::strategy_name(*opt.constraints));
  // What the graph was built from is not read again: freed now, the later
  // passes reuse its memory (a smaller heap, warmer caches: N = 1000 rods).
  resolved = ir::ResolvedModel{};
  expanded = ir::ExpandedProgram{};
  ast = ir::AstProgram{};
  if (selected) {
    const scene::SceneReport report = scene::prune_graph(graph, *selected, diags);
    if (failed()) return 1;
    if (opt.explain_scene) return finish(scene::explain(report));
  }
  if (opt.dump == Dump::Graph && !opt.dot) return finish(ir::print_graph(graph));

  ir::CausalGraph causal = causality::assign_causality(std::move(graph), diags);
  timed("causality");
  if (failed()) return 1;
  if (opt.dump == Dump::Graph) return finish(ir::print_graph_dot(causal.graph, /*with_causality=*/true));

  // The causality dump is written after reduce (it lists the loops), from
  // this text; otherwise the graph moves on instead of being copied.
  const std::string causality_text = opt.dump == Dump::Causality ? ir::print_causality(causal) : std::string();
  ir::EquationSystem equations = equations::generate(std::move(causal), diags);
  timed("equations");
  if (failed()) return 1;
  if (opt.dump == Dump::Equations) return finish(ir::print_equations(equations));
  if (opt.units != Options::Units::Off) {
    const units::UnitReport report = units::check_units(equations, diags, opt.units == Options::Units::Strict);
    timed("units");
    if (failed()) return 1;
    if (opt.units == Options::Units::Report) return finish(units::print_report(equations.graph, report));
    units::record_dimensions(equations.graph, report);
  }

  ir::ReducedSystem reduced = reduce::reduce(std::move(equations), diags, opt.energy_witness);
  timed("reduce");
  if (failed()) return 1;
  if (opt.dump == Dump::Causality) {
    // The causality report includes the algebraic loops, found when sorting.
    std::string text = causality_text;
    if (!strategy_report.empty()) text += strategy_report + "\n";
    text += "algebraic loops:";
    if (reduced.loops.empty()) text += " none\n";
    else text += "\n";
    for (const ir::AlgebraicLoop& l : reduced.loops) {
      std::string bonds;
      for (int b : l.bonds) bonds += (bonds.empty() ? "" : ", ") + std::to_string(reduced.graph.bonds[static_cast<std::size_t>(b)].number);
      text += "  bonds " + bonds + ": " + l.resolution + "\n";
    }
    text += "derivative causality handling:";
    if (reduced.derivative_causality.empty()) text += " none\n";
    else text += "\n";
    for (const std::string& s : reduced.derivative_causality) text += "  " + s + "\n";
    text += reduced.dae ? "form: DAE (IDA)\n" : "form: ODE\n";
    return finish(text);
  }
  if (opt.dump == Dump::Reduced) return finish(ir::print_reduced(reduced));

  codegen::EmitOptions emit;
  emit.library = opt.library;
  emit.outline = opt.outline == "always"  ? codegen::EmitOptions::Outline::always
                 : opt.outline == "never" ? codegen::EmitOptions::Outline::never
                                          : codegen::EmitOptions::Outline::automatic;
  emit.library_namespace = opt.library_namespace;
  if (selected) emit.scene = selected->name;
  emit.source_display = opt.input;
  if (opt.stats) {
    codegen::EmitStats stats;
    codegen::emit_cpp(reduced, sources, emit, &stats);
    return finish(codegen::format_stats(stats, opt.stats_csv));
  }
  if (!opt.fmu.empty()) return export_fmu(opt, reduced, sources, emit, err);
  std::string text = codegen::emit_cpp(reduced, sources, emit);
  timed("emit");
  const int rc = finish(text);
  timed("write");
  if (opt.exit_when_done) {
    // Freeing millions of expression nodes one by one, in no order the
    // caches like, would take another sixth of the run (N = 800 rods): the
    // process ends here instead, its output written and flushed.
    out.flush();
    err.flush();
    std::fflush(nullptr);
    std::_Exit(rc);
  }
  return rc;
}

}  // namespace mbgc::driver
