// causality/scap.hpp — pass 4: the Sequential Causality Assignment Procedure.
//
// 1. sources and elements whose shape fixes their causality (a non-square
//    TF/GY) — a conflict here is an error;
// 2. storage elements, preferring integral causality; a storage the
//    propagation has already forced the other way gets derivative causality;
// 3. remaining R elements, in the form their law is written (a choice: may
//    close an algebraic loop; a nonlinear law forced into the other form
//    becomes an implicit equation);
// 4. any bond still open (junction-structure loops): an arbitrary choice.
// After each step the junction, TF and GY constraints are propagated.
// Causality rules per element kind live in one table (kRules).
#pragma once

#include "ir/causal.hpp"
#include "ir/diagnostics.hpp"

namespace mbgc::causality {

ir::CausalGraph assign_causality(ir::BondGraph graph, ir::Diagnostics& diags);

}  // namespace mbgc::causality
