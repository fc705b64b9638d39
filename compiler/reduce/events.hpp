// reduce/events.hpp — the model's discontinuities, found in the reduced
// system: every step(x) whose argument changes during a run (it reads time or
// a variable) becomes an event. Between events the step is a constant (the
// generated model holds it as a mode, 0 or 1); the integrators locate the
// zero crossings of x (time events, x = t - t0, too) and the runtime switches
// the mode there, so that no integration step straddles a jump.
#pragma once

#include <vector>

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// Kinks in time become events too: min(a, b) and max(a, b) whose a - b
/// reads t but no variable (a motion profile's end, ramp(t0)) are rewritten
/// in s as a + (b - a) step(a - b) and b + (a - b) step(a - b).
void steps_for_time_kinks(ir::ReducedSystem& s);

/// The step nodes of s's expressions whose argument reads t or a variable,
/// each once, in the order first met (assignments in order, then state
/// derivatives, residuals, outputs, constraint rows).
std::vector<ir::EventRelation> find_events(const ir::ReducedSystem& s);

}  // namespace mbgc::reduce
