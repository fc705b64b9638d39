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

#include <string>

#include "ir/diagnostics.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

struct EmitOptions {
  bool library = false;          ///< emit the model class only (no main), for embedding
  std::string library_namespace = "mbgc_model";  ///< namespace of the class in the library form
  std::string source_display;    ///< source path shown in the banner
  std::string scene;             ///< the scene compiled (mbgc --scene), if any
  std::string version = MBGC_VERSION;
};

/// Empty if `name` can be the namespace of --library's class, else why not.
std::string namespace_problem(const std::string& name);

std::string emit_cpp(const ir::ReducedSystem& system, const ir::SourceManager& sources,
                     const EmitOptions& options);

}  // namespace mbgc::codegen
