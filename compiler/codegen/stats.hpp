// codegen/stats.hpp — mbgc --stats from the model class as built: each
// method's lines and bytes as printed, and the operations and linear solves
// the emitter counted while it wrote them (codegen/emit_cpp.cpp).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "codegen/cpp.hpp"
#include "codegen/emit_cpp.hpp"
#include "ir/expr.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// What a method's expressions and linear solves cost per call, counted as they are printed.
struct MethodCost {
  ir::CppOps ops;
  std::vector<std::size_t> solves;
};

/// The statistics of class `c`, printed as `file`; `costs` by method signature.
EmitStats collect_stats(const CppClass& c, const std::string& file, const std::map<std::string, MethodCost>& costs,
                        const ir::ReducedSystem& s);

}  // namespace mbgc::codegen
