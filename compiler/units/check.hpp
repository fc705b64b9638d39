// units/check.hpp — pass: the dimensions of every quantity, inferred over the
// equations, and the contradictions reported.
//
// Every parameter and variable has an unknown dimension; each equation says
// its two sides agree, each bond that its effort times its flow is a power,
// each state that its derivative is it per second, each declared unit
// (`param k = 3e4 {N/m}`) what it is. Dimensions multiply, so in their
// exponents these are linear equations, solved as they come by elimination
// (unification over an abelian group, as F#'s units of measure): an unknown
// no equation fixes stays free, and a model without units infers what it can.
// An equation that contradicts those before it is an error at its model line,
// with what each side is and where the units it rests on were declared.
//
// The radian is set aside in the checking (a torque times an angular rate is a
// power; `sin` takes an angle or a number); it is kept in what was declared.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ir/diagnostics.hpp"
#include "ir/equations.hpp"
#include "units/unit.hpp"

namespace mbgc::units {

struct UnitReport {
  /// Per parameter and per output of the equation system's graph: the
  /// dimension declared, else inferred, else nullopt (nothing fixes it).
  std::vector<std::optional<Dimension>> params;
  std::vector<std::optional<Dimension>> outputs;
};

/// Infers and checks. `strict`: a parameter whose unit is neither declared
/// nor inferred is an error too.
UnitReport check_units(const ir::EquationSystem& sys, ir::Diagnostics& diags, bool strict = false);

/// Writes each parameter's and output's dimension (`report`) into the
/// graph, for the passes after this one (Parameter::dimension, Output::dimension).
void record_dimensions(ir::BondGraph& g, const UnitReport& report);

/// `mbgc --units report`: every parameter and output with its unit, and
/// whether the model declares it or it was inferred.
std::string print_report(const ir::BondGraph& g, const UnitReport& report);

}  // namespace mbgc::units
