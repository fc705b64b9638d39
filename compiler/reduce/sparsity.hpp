// reduce/sparsity.hpp — pass 6b: which unknowns each DAE residual reads; and
// the query an FMU's ModelStructure asks: which states (and whether time) an
// ODE's derivatives, outputs and event indicators read.
//
// IDA's Newton matrix is J = dF/dy + c_j dF/dy'. Its column k holds the rows
// of the residuals that read y_k or y'_k, directly or through the assignments
// the residual section computes first (a linear block's unknowns read all its
// inputs). The runtime uses this pattern for a sparse direct solver (KLU) and
// to difference several columns of J with one residual evaluation.
#pragma once

#include <vector>

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Fills s.residual_pattern (per column of J, its rows, ascending) for a DAE.
void residual_sparsity(ir::ReducedSystem& s);

/// What a value reads of the state: state indices, ascending, and time.
struct StateReads {
  std::vector<int> states;
  bool time = false;
};

/// What each of `values` reads, directly or through the assignments (in
/// their evaluation order; a linear block's unknowns read all its inputs).
/// A superset of what the value truly depends on: a term that vanishes at
/// run time, or one a mode switches off, still counts.
std::vector<StateReads> state_reads(const ir::ReducedSystem& s, const std::vector<ir::Expr>& values);

}  // namespace mbgc::reduce
