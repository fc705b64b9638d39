// codegen/cse.hpp — common subexpressions of a method, found by a pass over
// its statements before they are printed.
//
// Every non-trivial subexpression that the statements' values use more than
// once is defined once, as `const double cseN = ...;`, right before the
// statement that first needs it (before its group, see
// CppStmt::with_previous), innermost first. A statement that may name its
// value (an equation's unknown, a derived constant) and whose whole value
// recurs becomes that name itself: `hub_f = hub_p / J_hub`, reused, rather
// than a cseN copy. codegen/render.hpp then prints each value once, a named
// node as its name.
#pragma once

#include <cstddef>
#include <string>
#include <unordered_map>
#include <vector>

#include "codegen/cpp.hpp"
#include "ir/expr.hpp"

namespace mbgc::codegen {

/// Expressions with a name in the generated code.
using ExprNames = std::unordered_map<ir::Expr, std::string, ir::ExprHash, ir::ExprEqual>;

/// The pass over `body[from..]` (one method's section: what the methods
/// before it defined is out of its scope). `known` are named before it
/// starts (the derived constants, members computed in initial(); an
/// outlined function's inputs): not shared again, read by their names.
/// `counter` numbers the cseN names, one count per file, so that each name
/// is unique when codegen/split makes a local a member.
void share_subexpressions(std::vector<CppStmt>& body, std::size_t from, const ExprNames& known, int& counter);

}  // namespace mbgc::codegen
