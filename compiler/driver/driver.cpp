#include "driver/driver.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "causality/scap.hpp"
#include "codegen/emit_cpp.hpp"
#include "elaborate/unroll.hpp"
#include "multibody/expand.hpp"
#include "equations/generate.hpp"
#include "graph/build_graph.hpp"
#include "ir/print.hpp"
#include "parse/parse.hpp"
#include "reduce/reduce.hpp"
#include "sema/resolve.hpp"

namespace mbgc::driver {
namespace {

/// Write via a temporary file and rename, so a failed write never leaves a partial file.
bool write_atomically(const std::string& path, const std::string& text) {
  std::string tmp = path + ".mbgc-tmp";
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
    if (!write_atomically(opt.output, text)) {
      err << "mbgc: error: cannot write `" << opt.output << "`\n";
      return 3;
    }
    if (!opt.depfile.empty()) {
      std::string deps = opt.output + ":";
      for (int f = 0; f < sources.count(); ++f) deps += " " + sources.file(f).display_path;
      if (!write_atomically(opt.depfile, deps + "\n")) {
        err << "mbgc: error: cannot write `" << opt.depfile << "`\n";
        return 3;
      }
    }
    return 0;
  };

  ir::AstProgram ast = parse::load_program(opt.input, sources, diags);
  if (failed()) return 1;
  if (opt.dump == Dump::Ast) return finish(ir::print_ast(ast));

  ast = elaborate::unroll_loops(ast, opt.overrides, diags);
  if (failed()) return 1;
  ast = multibody::expand(ast, sources, diags, {opt.constraints, opt.search_dirs});
  if (failed()) return 1;
  if (opt.dump == Dump::Expanded) return finish(ir::print_ast(ast));

  ir::ResolvedModel resolved = sema::resolve(ast, opt.input, diags);
  if (failed()) return 1;
  ir::BondGraph graph = graph::build_graph(resolved, sources, diags);
  if (failed()) return 1;
  if (opt.dump == Dump::Graph && !opt.dot) return finish(ir::print_graph(graph));

  ir::CausalGraph causal = causality::assign_causality(std::move(graph), diags);
  if (failed()) return 1;
  if (opt.dump == Dump::Graph) return finish(ir::print_graph_dot(causal.graph, /*with_causality=*/true));

  ir::EquationSystem equations = equations::generate(causal, diags);
  if (failed()) return 1;
  if (opt.dump == Dump::Equations) return finish(ir::print_equations(equations));

  ir::ReducedSystem reduced = reduce::reduce(std::move(equations), diags);
  if (failed()) return 1;
  if (opt.dump == Dump::Causality) {
    // The causality report includes the algebraic loops, found when sorting.
    std::string text = ir::print_causality(causal);
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
  emit.source_display = opt.input;
  return finish(codegen::emit_cpp(reduced, sources, emit));
}

}  // namespace mbgc::driver
