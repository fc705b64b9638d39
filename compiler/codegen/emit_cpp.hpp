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
  std::string source_display;    ///< source path shown in the banner
  std::string version = MBGC_VERSION;
};

std::string emit_cpp(const ir::ReducedSystem& system, const ir::SourceManager& sources,
                     const EmitOptions& options);

}  // namespace mbgc::codegen
