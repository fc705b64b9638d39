// reduce/nominal.hpp — pass 6d: each state's nominal size.
//
// One absolute tolerance for every unknown would resolve a 1e-9 kg body's momenta
// (about 1e-9 kg m/s) only to atol, and a 1e3 kg body's to atol / 1e3 of its
// velocity. The integrators therefore take atol x nominal(i) for unknown i
// (mbgrt::Model::nominal): a momentum's nominal is its inertia times a unit
// rate (p = I f: the largest diagonal entry of the element's I at the initial
// state, a mass or a moment of inertia), so that atol is, for every body, a
// tolerance on its velocity; a modal
// coordinate with a validity limit (a beam's) takes that limit; every other
// unknown (a position, an angle, a charge, a multiplier) takes 1, a unit of
// its own quantity.
#pragma once

#include <vector>

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Fills s.nominal: per state, its nominal size, an expression in the
/// parameters (the emitter evaluates it once per run, after --set).
void nominal_values(ir::ReducedSystem& s);

}  // namespace mbgc::reduce
