// reduce/reduce.hpp — pass 6: equation system -> sorted, reduced system.
//
//  1. derivative causality: der(x) of a dependent storage is expanded into the
//     states it depends on and differentiated symbolically (chain rule); the
//     dependent state is thereby eliminated (the minimal-variable form);
//  2. alias elimination (a = ±b);
//  3. sorting into strongly connected blocks (Tarjan): a block of one equation
//     is solved for its unknown; a larger block is an algebraic loop, solved
//     symbolically by Gaussian elimination when linear in its unknowns, else
//     left to IDA as a DAE (the model becomes a DAE);
//  4. dead-equation removal (reduce/slice.hpp): only what the states'
//     derivatives (or the DAE residuals), the outputs, the events and the
//     contacts need is kept.
// Constant folding happens in every expression constructor; common
// subexpressions are shared when the emitter prints.
#pragma once

#include "ir/diagnostics.hpp"
#include "ir/equations.hpp"
#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// energy_witness: build the energy balance (reduce/energy.hpp); false
/// (mbgc --no-energy-witness) leaves it out, and the model says so.
ir::ReducedSystem reduce(ir::EquationSystem system, ir::Diagnostics& diags, bool energy_witness = true);

}  // namespace mbgc::reduce
