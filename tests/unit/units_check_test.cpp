// Unit tests for units/check: dimensions inferred over the equations of
// models written without units, with some, and with all; what --units report
// lists. The contradictions' messages are golden tests
// (tests/golden/bad/units_*.mbg).
//
// Test suites are named UnitsCheck* so that `ctest -R UnitsCheck` selects them.
#include "units/check.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "driver/driver.hpp"
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

TEST(UnitsCheck, ALiteralsUnitIsNotLostByTheIdentitiesOfOne) {
  // `1 {s} * v` is a length (x * 1 = x holds for a plain 1 only), and so is `-2 {s} * v`
  for (const char* q0 : {"1 {s} * v", "-2 {s} * v", "v / (1 {1/s})"}) {
    Checked k = check(std::string("param m = 3 {kg}\nparam k = 50 {N/m}\nparam v = 0.2 {m/s}\nI mass = m\n"
                                  "C spring = 1/k { q0 = ") + q0 + " }\n1 j : -> mass, spring\n");
    EXPECT_EQ(k.c->diags.error_count(), 0) << q0 << ": " << k.messages;
  }
  Checked bad = check("param m = 3 {kg}\nparam k = 50 {N/m}\nparam v = 0.2 {m/s}\nI mass = m\n"
                      "C spring = 1/k { q0 = 1 {N} * v }\n1 j : -> mass, spring\n");
  EXPECT_EQ(bad.c->diags.error_count(), 1) << bad.messages;
}

TEST(UnitsCheck, AnInitialValueThroughItsEffortIsNotReadAsTheState) {
  // q0 then e0: the last one wins (q0 = C e0), and C * 1 {N} folds to C: not checked as q
  Checked k = check("param c = 0.01 {m/N}\nC spring = c { q0 = 0.1 {m}; e0 = 1 {N} }\nI mass = 2 {kg}\n"
                    "1 j : -> mass, spring\n");
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

/// mbgc on `model` (written to a file of the test's name) with --units `units`: its exit status, output and errors.
struct Driven {
  int status;
  std::string out, err;
};
Driven drive(const std::string& model, mbgc::driver::Options::Units units) {
  const std::string path =
      std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_units.mbg";
  std::ofstream(path) << model;
  mbgc::driver::Options opt;
  opt.input = path;
  opt.units = units;
  std::ostringstream out, err;
  const int status = mbgc::driver::compile(opt, out, err);
  std::remove(path.c_str());
  return {status, out.str(), err.str()};
}

TEST(UnitsCheck, TheMultibodyLayerStatesWhatItWrites) {
  // a body's mass, inertia and points, a joint's frame and a force's spring: what the
  // layer writes of a model without a unit is in the report (where it is a parameter,
  // not folded to a number), and a user's expression that reads one is held to it
  const std::string pendulum = R"(
param m = 3
param J = 0.01
param L = 0.5
param k = 100
param g = 9.81
gravity = [0, -g, 0]
ground { point pivot = [0, 0, 0] }
body arm {
  mass = m
  inertia = diag(J, J, 2 * J)
  point tip = [L, 0, 0]
}
joint hinge revolute(ground.pivot, arm) { axis = [0, 0, 1] }
force spring(ground.pivot, arm.tip) { stiffness = k; length = 0.8 * L }
)";
  using Units = mbgc::driver::Options::Units;
  const Driven report = drive(pendulum, Units::Report);
  ASSERT_EQ(report.status, 0) << report.err;
  for (const char* line : {"arm.mass                 kg             stated by the multibody layer",
                           "arm.inertia[1,1]         kg*m^2         stated by the multibody layer",
                           "arm.tip[1]               m              stated by the multibody layer",
                           "spring.stiffness         N/m            stated by the multibody layer",
                           "m                        kg             inferred"})
    EXPECT_NE(report.out.find(line), std::string::npos) << line << "\n" << report.out;

  // the generated parameters() gives each its SI unit (the simulator's --list-parameters shows it)
  const Driven code = drive(pendulum, Units::Check);
  ASSERT_EQ(code.status, 0) << code.err;
  EXPECT_NE(code.out.find(R"({"arm.mass", std::numeric_limits<double>::quiet_NaN(), "= m", "kg"})"), std::string::npos)
      << code.out;
  EXPECT_NE(code.out.find(R"({"m", 3.0, "", "kg"})"), std::string::npos) << code.out;

  const Driven wrong = drive(pendulum + "output w = arm.mass {m}\n", Units::Check);
  EXPECT_NE(wrong.status, 0);
  EXPECT_NE(wrong.err.find("the units of output w do not agree: its value is kg, its unit {m} is m"), std::string::npos)
      << wrong.err;
}

}  // namespace
