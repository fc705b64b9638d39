// codegen/derived_constants.hpp — the derived constants: subexpressions that
// depend on parameters only, computed once per run in initial() and kept as
// members of the model class instead of at every call of the methods that
// use them.
#pragma once

#include <vector>

#include "codegen/cse.hpp"
#include "ir/expr.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// The largest subexpressions of `s`'s equations that depend on parameters
/// only (1/J, m*g, ...) and cost something at run time: each one not in
/// `names` yet gets its member's name there ("derived3_") and is appended
/// to `order` (in first-use order).
void find_derived_constants(const ir::ReducedSystem& s, ExprNames& names, std::vector<ir::Expr>& order);

}  // namespace mbgc::codegen
