// equations/generate.hpp — pass 5: causal graph -> equation system.
//
// Writes each element's constitutive law and each junction's balance in the
// direction causality gives it: one scalar equation per unknown. Storage in
// integral causality contributes a state and `der(state) = input`; storage in
// derivative causality contributes `output = der(law)`, removed later by reduce.
#pragma once

#include "ir/causal.hpp"
#include "ir/diagnostics.hpp"
#include "ir/equations.hpp"

namespace mbgc::equations {

ir::EquationSystem generate(ir::CausalGraph causal, ir::Diagnostics& diags);

}  // namespace mbgc::equations
