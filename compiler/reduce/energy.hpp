// reduce/energy.hpp — pass 2a: the energy balance, a witness of the
// integration's error that needs no reference run (issue 19).
//
// A bond graph knows where energy goes: junctions and two-ports conserve it,
// storages hold it, every other one-port exchanges it through its bonds. So
//
//   H(x(t)) - H(x(0)) = integral of (P_supplied - P_absorbed) dt
//
// holds exactly for the model's equations, where H is the stored energy (a
// function of the state), P_supplied the power the sources deliver and
// P_absorbed the power the dissipators (R), the constraints and contacts (CN)
// and the storages whose energy is not a function of their state take. What
// a run's numbers miss of it is integration error. The runtime integrates the
// two powers beside the state (the generated power(), codegen/energy.hpp)
// and evaluates H at the output points (stored_energy()).
//
// A storage with a linear law (I: p = I f, C: q = C e) holds 1/2 p.f or
// 1/2 q.e, in terms of its bond's variables. A storage with a nonlinear law
// (e = phi(q), f = phi(p)), or with a linear one whose modulus reads a
// variable or the time in a way not handled below, is counted by the power
// into it instead, and named in `unwitnessed`: its own integration error then
// does not show. With no storage left to witness the balance would hold by
// construction, and the model has none.
//
// A modulated inertia p = M(q) f whose M reads only displacements (a
// flexible body's mass matrix over its modal coordinates) and the time still
// holds 1/2 f.M f; 1/2 f.(dM/dt) f leaves through the modulation and is
// counted as absorbed (dq/dt is a flow: no accelerations are needed).
//
// A source whose value follows the motion (a joint's `torque = T - c *
// J.rate`, a force element's `damping`) is split: what it imposes with every
// flow at rest is supplied, and the rest of its power is absorbed while it
// takes power (supplied while it gives), so a damper written as a source
// makes the model dissipative.
#pragma once

#include "ir/reduced.hpp"

namespace mbgc::reduce {

/// s.energy from s.graph, in terms of the graph's variables (before alias
/// elimination, which then resolves it like the outputs).
void energy_balance(ir::ReducedSystem& s);

/// After sorting: the balance is dropped (s.energy.available = false, with
/// the reason) if a term reads a variable no generated method computes.
void check_energy_inputs(ir::ReducedSystem& s);

}  // namespace mbgc::reduce
