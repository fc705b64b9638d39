// codegen/emit_cpp.hpp — pass 7: reduced system -> one C++ source file.
//
// The output is ACSL-shaped: a banner, then a class deriving from
// mbgrt::Model with the sections CONSTANTS/PARAMETERS (initial()),
// DERIVATIVE (derivative() or residual() for DAEs), OUTPUT (outputs()) and
// TERMINAL (terminal()); every equation carries a comment naming the model
// line it came from. Code is built as a small C++ syntax tree (codegen/cpp.hpp)
// and printed once into the wrapper template (templates/simulator.cpp.in).
// The output is deterministic: same model, same bytes.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"
#include "ir/expr.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

struct EmitOptions {
  bool library = false;          ///< emit the model class only (no main), for embedding
  std::string library_namespace = "mbgc_model";  ///< namespace of the class in the library form
  std::string source_display;    ///< source path shown in the banner
  std::string scene;             ///< the scene compiled (mbgc --scene), if any
  std::string version = MBGC_VERSION;
  /// Bodies with the same equations share one function (codegen/outline.hpp):
  /// automatic: where the inline code would not fit the instruction cache.
  enum class Outline { automatic, always, never } outline = Outline::automatic;
  /// Instead of main(): what follows the class, given its name (mbgc --fmu's
  /// table of variables, fmu/interface.hpp); the class stays file-local.
  std::function<std::string(const std::string& class_name)> entry_point;
};

/// Empty if `name` can be the namespace of --library's class, else why not.
std::string namespace_problem(const std::string& name);

/// What one generated method costs per call (mbgc --stats).
struct FunctionStats {
  std::string name;         ///< the method's name ("derivative", "residual", ...)
  std::size_t lines = 0;    ///< its lines in the file: doc comment, signature, body, closing brace
  std::size_t bytes = 0;    ///< the bytes of those lines (as indented in the file)
  ir::CppOps ops;           ///< operations of its expressions, as written (see ir::to_cpp)
  std::vector<std::size_t> solves;  ///< the size n of each mbgrt::solve_linear(n, ...) it calls
  std::size_t solve_ops = 0;        ///< their arithmetic: sum of solve_linear_ops(n)
  std::size_t total() const { return ops.total() + solve_ops; }
};

struct EmitStats {
  std::string model;
  bool dae = false;
  std::size_t states = 0, algebraic = 0;
  std::vector<FunctionStats> functions;  ///< every method of the model class, in file order
  std::size_t file_lines = 0, file_bytes = 0;
};

/// Arithmetic (+ - * /) of mbgrt::solve_linear on an n x n system when no
/// multiplier is zero (the loop skips rows whose multiplier is exactly 0):
/// elimination sum_{m<n} m(2m+3), back substitution n^2, in all
/// (4n^3 + 9n^2 - 7n) / 6 (1, 9, 28, 62 for n = 1..4; about 2n^3/3). The
/// pivot search (fabs and comparisons) and the multiplier-is-zero tests are
/// not included.
std::size_t solve_linear_ops(std::size_t n);

/// `stats`, if given, receives the cost of every method of the model class,
/// counted while the text is written (the text is the same either way).
std::string emit_cpp(const ir::ReducedSystem& system, const ir::SourceManager& sources,
                     const EmitOptions& options, EmitStats* stats = nullptr);

/// mbgc --stats: a table (text) or CSV with one row per method, then `total`
/// (the methods' sums) and `file` (the whole file's lines and bytes).
std::string format_stats(const EmitStats& stats, bool csv);

}  // namespace mbgc::codegen
