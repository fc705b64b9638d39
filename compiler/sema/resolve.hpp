// sema/resolve.hpp — pass 2: AST -> resolved model.
//
// Flattens component instances into dotted names, orders and lowers the
// parameters (a cycle is an error), binds both ends of every bond to a node,
// and reads the simulate { } block. Unknown names get "did you mean" hints.
#pragma once

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/resolved.hpp"

namespace mbgc::sema {

ir::ResolvedModel resolve(const ir::AstProgram& program, const std::string& source_file,
                          ir::Diagnostics& diags);

}  // namespace mbgc::sema
