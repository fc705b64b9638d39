// sema/resolve.hpp — the expanded program (ir/expanded.hpp) -> resolved model.
//
// Flattens component instances into dotted names, orders and lowers the
// parameters (a cycle is an error), binds both ends of every bond to a node,
// and reads the simulate { } block. Unknown names get "did you mean" hints.
#pragma once

#include "ir/expanded.hpp"
#include "ir/diagnostics.hpp"
#include "ir/limits.hpp"
#include "ir/resolved.hpp"

namespace mbgc::sema {

/// A model that grows past limits.model_size elements, junctions and bonds
/// is an error at the top-level statement that grew it.
ir::ResolvedModel resolve(const ir::ExpandedProgram& program, const std::string& source_file,
                          ir::Diagnostics& diags, const ir::Limits& limits = {});

}  // namespace mbgc::sema
