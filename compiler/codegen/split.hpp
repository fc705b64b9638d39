// codegen/split.hpp — a method too long for the C++ compiler, cut into parts.
//
// g++'s register allocation grows faster than linearly with a function's
// length: the derivative of a 100-rod chain in joint coordinates is one
// function of about 8,000 statements, and g++ -O2 took 20 s for it against
// 5 s for the 50-rod chain. A long body is therefore cut, between statements,
// into parts of at most `max_lines` lines (private methods the original one
// calls in order). A local that a later part reads becomes a member of the
// same name, so the text of every statement stays what it was; only its
// `const double` goes. The unknowns the method starts by reading (`const
// double x = y[3];`) are no members: each part reads those it uses. The cut
// falls where an equation's comment starts a new run, never inside a linear
// block's arrays.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "codegen/cpp.hpp"

namespace mbgc::codegen {

struct SplitMethod {
  CppFunction method;               ///< the original signature, its body the calls of the parts
  std::vector<CppFunction> parts;   ///< private methods NAME_part1, NAME_part2, ...
  std::vector<std::string> members; ///< locals a later part reads: now `double NAME = 0.0;` members
};

/// Nothing if `f`'s body has at most `max_lines` lines (or cannot be cut).
std::optional<SplitMethod> split_method(const CppFunction& f, std::size_t max_lines);

/// The method name in a signature: "void derivative(double t, ...) override" -> "derivative".
std::string method_name(const std::string& signature);

}  // namespace mbgc::codegen
