// codegen/energy.hpp — the generated model's energy witness (reduce/energy.hpp):
// stored_energy() gives H and power() the sources' and the absorbers' power
// at (t, y) (each a section of equations the emitter writes, like the
// outputs: derivative() and residual() are untouched), and the model says
// what the balance leaves out.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "codegen/cpp.hpp"
#include "ir/reduced.hpp"

namespace mbgc::codegen {

/// A model line's location as the generated comments print it ("file.mbg:12:3").
using Where = std::function<std::string(const ir::SourceLoc&)>;

/// H, the sum of the stored terms, for the emitter's stored_energy section.
ir::Expr stored_energy_value(const ir::ReducedSystem& s);
/// The supplied and the absorbed power, for the emitter's power section.
std::vector<ir::Expr> power_values(const ir::ReducedSystem& s);

/// The two methods the emitter writes as sections (values at (t, y, yp)).
struct EnergyMethods {
  CppFunction stored;  ///< stored_energy()
  CppFunction power;   ///< power()
};

/// has_energy_balance(), energy_note() and the two methods, each headed by
/// the terms it sums; or, when the balance is not available, energy_note()
/// saying why.
void add_energy_methods(CppClass& c, const ir::ReducedSystem& s, const Where& where, std::optional<EnergyMethods> methods);

}  // namespace mbgc::codegen
