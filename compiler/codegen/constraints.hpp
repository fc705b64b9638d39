// codegen/constraints.hpp — the generated model's constraint rows (CN): how
// many, their names, whether the model enforces them (lagrange) or only
// pulls them back (penalty), which are held, and where a DAE's multipliers
// sit in y. The rows' values g and gdot and their Jacobian are sections of
// equations, written by the emitter like the outputs.
#pragma once

#include "codegen/cpp.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// state_count() (a DAE), position_constraint_count(),
/// velocity_constraint_count(), constraints_enforced(), constraint_held()
/// (where a joint is cut), constraint_name() and, in a DAE,
/// multiplier_index() and stabiliser_index(). For a model with constraints.
void add_constraint_methods(CppClass& c, const ir::ReducedSystem& s);

}  // namespace mbgc::codegen
