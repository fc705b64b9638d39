// codegen/render.hpp — a method's expressions printed, once, after
// codegen/cse.hpp has named what they share.
#pragma once

#include <cstddef>
#include <vector>

#include "codegen/cpp.hpp"
#include "codegen/cse.hpp"
#include "ir/expr.hpp"

namespace mbgc::codegen {

/// Prints the values of `body[from..]` in order through `names`: a node
/// `known` names, or one a statement above named (CppStmt::names_value),
/// as that name, as a variable would be. An Array becomes the Lines of its
/// initialisation. The operations of the printed text are added to `ops`.
void render(std::vector<CppStmt>& body, std::size_t from, const ExprNames& known, const ir::Namer& names, ir::CppOps* ops);

}  // namespace mbgc::codegen
