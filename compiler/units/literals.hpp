// units/literals.hpp — the unit written on a literal (`2 {mm}`), checked where
// it is written, against the dimension of the setting it gives. A value that
// reads a name is left to the units pass (check.hpp); the literals are
// compared here, before lowering brings them to SI numbers.
#pragma once

#include <string>

#include "ir/ast.hpp"
#include "ir/diagnostics.hpp"
#include "units/unit.hpp"

namespace mbgc::units {

/// Reports each literal of `value` whose unit is not of `dimension` (the
/// entries of a vector or matrix, and a scaled literal, `2 * 3 {mm}`, have
/// the setting's unit); `what` names the setting ("the mass of body `arm`").
/// False if one was reported.
bool check_literal_units(const ir::AstExpr& value, const Dimension& dimension, const std::string& what,
                         ir::Diagnostics& diags);

/// Whether `e` reads a name (a parameter, a quantity, t): then the units
/// pass infers what it is.
bool reads_a_name(const ir::AstExpr& e);

}  // namespace mbgc::units
