// reduce/sparsity.hpp — pass 6b: which unknowns each DAE residual reads.
//
// IDA's Newton matrix is J = dF/dy + c_j dF/dy'. Its column k holds the rows
// of the residuals that read y_k or y'_k, directly or through the assignments
// the residual section computes first (a linear block's unknowns read all its
// inputs). The runtime uses this pattern for a sparse direct solver (KLU) and
// to difference several columns of J with one residual evaluation.
#pragma once

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Fills s.residual_pattern (per column of J, its rows, ascending) for a DAE.
void residual_sparsity(ir::ReducedSystem& s);

}  // namespace mbgc::reduce
