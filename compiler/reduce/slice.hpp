// reduce/slice.hpp — dead-equation removal, the last step of reduce: which
// sorted assignments each generated method needs (the state derivatives or
// DAE residuals, the outputs, the Jacobian, the constraints, the events, the
// contacts' rates and their tangential rows), and the assignments nothing
// needs dropped.
#pragma once

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Fills s's for_* slices (indices into s.assignments, in order), removes
/// the assignments none of them reads and renumbers the slices.
void slice(ir::ReducedSystem& s);

}  // namespace mbgc::reduce
