// ir/declared_unit.hpp — a unit the model states, `{N/m}`, and where.
#pragma once

#include "ir/diagnostics.hpp"
#include "units/unit.hpp"

namespace mbgc::ir {

struct DeclaredUnit {
  units::Unit unit;
  SourceLoc loc;  // of the text inside the braces
};

}  // namespace mbgc::ir
