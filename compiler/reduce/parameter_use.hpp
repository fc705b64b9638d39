// reduce/parameter_use.hpp — which parameters a run reads. A top-level
// `param` the compiler used up (a loop bound, a beam's length or mode count,
// evaluated while the model was elaborated) still stands in the bond graph's
// list, but nothing the simulator computes reads it: setting it at run time
// changes nothing. An FMU lists such a parameter as a constant.
#pragma once

#include <vector>

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Per parameter of s.graph.params: whether any expression of the reduced
/// system reads it, directly or through another parameter that is read. A
/// superset: the element laws and values of the bond graph count as read.
std::vector<bool> parameters_read(const ir::ReducedSystem& s);

}  // namespace mbgc::reduce
