// Unit tests for units/check: dimensions inferred over the equations of
// models written without units, with some, and with all; what --units report
// lists. The contradictions' messages are golden tests
// (tests/golden/bad/units_*.mbg).
//
// Test suites are named UnitsCheck* so that `ctest -R UnitsCheck` selects them.
#include "units/check.hpp"

#include <gtest/gtest.h>

#include <string>

#include "pipeline.hpp"

namespace {

using namespace mbgc_test;
namespace units = mbgc::units;

struct Checked {
  std::unique_ptr<Compiled> c;
  units::UnitReport report;
  std::string messages;
};

Checked check(const std::string& model, bool strict = false) {
  Checked out{run(model, Stage::Equations), {}, {}};
  EXPECT_TRUE(out.c->ok()) << out.c->messages();
  out.report = units::check_units(out.c->equations, out.c->diags, strict);
  out.messages = out.c->messages();
  return out;
}

std::string unit_of_param(const Checked& k, const std::string& name) {
  const auto& params = k.c->equations.graph.params;
  for (std::size_t i = 0; i < params.size(); ++i)
    if (params[i].name == name) return k.report.params[i] ? units::format(*k.report.params[i]) : "?";
  ADD_FAILURE() << "no parameter " << name;
  return "";
}

const char* kMotor = R"(
param V = 12 {V}
param R = 1.2 {Ohm}
param L = 0.05
param K = 0.1 {N*m/A}
param J = 0.01
param b = 1e-4
Se supply = V
R winding = R
I inductance = L
GY motor = K
I rotor = J
R friction = b
1 circuit : supply -> winding, inductance, motor.p1
1 shaft : motor.p2 -> rotor, friction
output omega = rotor.f
output i = inductance.f {A}
)";

TEST(UnitsCheck, WhatTheDeclaredUnitsFixIsInferredThroughTheGraph) {
  Checked k = check(kMotor);
  EXPECT_EQ(k.c->diags.error_count(), 0) << k.messages;
  EXPECT_EQ(unit_of_param(k, "L"), "H");            // V = L di/dt
  EXPECT_EQ(unit_of_param(k, "J"), "kg*m^2");       // N*m = J domega/dt
  EXPECT_EQ(unit_of_param(k, "b"), "N*m*s");        // N*m = b omega (rad set aside)
  const auto& outputs = k.c->equations.graph.outputs;
  ASSERT_EQ(outputs.size(), 2u);
  ASSERT_TRUE(k.report.outputs[0]);
  EXPECT_EQ(units::format(*k.report.outputs[0]), "1/s");
}

TEST(UnitsCheck, AModelWithoutUnitsChecksAndLeavesThemOpen) {
  Checked k = check("param m = 2\nparam c = 3\nI mass = m\nR damper = c\n1 body : -> mass, damper\n");
  EXPECT_EQ(k.c->diags.error_count(), 0) << k.messages;
  EXPECT_EQ(unit_of_param(k, "m"), "?");
  EXPECT_EQ(unit_of_param(k, "c"), "?");
}

TEST(UnitsCheck, NumbersInAnElementsValueCarryWhateverUnitTheyNeed) {
  // `I m = 1` writes p = f once folded; `Se f = step(0, 1)` is heaviside(t): neither is a contradiction
  Checked k = check("Se push = step(0, 1)\nI m = 1\nC c = 0.5\nR r = 2\n1 j : push -> m, c, r\n");
  EXPECT_EQ(k.c->diags.error_count(), 0) << k.messages;
}

TEST(UnitsCheck, StrictAsksForEveryParametersUnit) {
  // m is inferred (kg: c and a power fix the flow, the momentum's rate the effort);
  // g is read by an output only, which fixes nothing
  Checked k = check("param m = 2\nparam c = 3 {N*s/m}\nparam g = 2\nI mass = m\nR damper = c\n"
                    "1 body : -> mass, damper\noutput y = g * mass.f\n",
                    true);
  EXPECT_EQ(unit_of_param(k, "m"), "kg");
  EXPECT_EQ(k.c->diags.error_count(), 1) << k.messages;
  EXPECT_NE(k.messages.find("the unit of parameter `g` is neither declared nor inferred"), std::string::npos) << k.messages;
}

TEST(UnitsCheck, TheReportSaysWhatIsDeclaredAndWhatInferred) {
  Checked k = check(kMotor);
  std::string text = units::print_report(k.c->equations.graph, k.report);
  EXPECT_NE(text.find("V                        V              declared"), std::string::npos) << text;
  EXPECT_NE(text.find("L                        H              inferred"), std::string::npos) << text;
  EXPECT_NE(text.find("i                        A              declared"), std::string::npos) << text;
}

}  // namespace
