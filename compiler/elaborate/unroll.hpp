// elaborate/unroll.hpp — pass 1b: `for` loops -> repeated statements.
//
// `for i in 1..N { ... }` is replaced by its body once per value of i, with i
// substituted: as a number inside expressions, and inside the `{expr}`
// interpolations of names (`link{i-1}.tip` becomes `link2.tip` for i = 3).
// Loop bounds are evaluated at compile time from numbers and top-level
// parameters; `overrides` (mbgc --set NAME=VALUE) replace parameter values
// first, so one model file gives the chain with N = 2, 8 or 32. An overridden
// parameter's declaration is rewritten to the new value, so the generated
// simulator reports the N it was built with.
#pragma once

#include <map>
#include <string>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "ir/limits.hpp"

namespace mbgc::elaborate {

/// A loop longer than limits.loop_iterations, or nested loops that unroll
/// into more than limits.unrolled_work statements, is an error at the loop.
ir::AstProgram unroll_loops(const ir::AstProgram& program, const std::map<std::string, double>& overrides,
                            ir::Diagnostics& diags, const ir::Limits& limits = {});

}  // namespace mbgc::elaborate
