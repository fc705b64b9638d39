// multibody/units.hpp — the multibody layer's last pass: the units of the
// values users write in its statements (units.cpp says which). In: the Model,
// the finished Quantities table, the quantities user expressions read
// (QuantityRewriter::used, rewrite.hpp) and the diagnostics, where a literal
// of the wrong unit is an error. Out: what the units pass (units/check) is
// to infer and compare.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"
#include "ir/expanded.hpp"
#include "multibody/model.hpp"
#include "multibody/quantities.hpp"

namespace mbgc::multibody::detail {

std::vector<ir::ExpandedUnitCheck> state_units(const Model& m, const Quantities& quantities,
                                               const std::set<std::string>& used, SymbolIds& symbols,
                                               ir::Diagnostics& diags);

}  // namespace mbgc::multibody::detail
