// Unit tests for units/unit: dimensions as products of rational powers, the
// unit notation inside braces and the factors that bring a value to SI,
// checked against the definitions of the units (BIPM's SI brochure), and how
// a dimension is written back for a user.
//
// Test suites are named Units* so that `ctest -R Units` selects them.
#include "units/unit.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <string>

namespace {

using mbgc::units::Base;
using mbgc::units::Dimension;
using mbgc::units::parse_unit;
using mbgc::units::Rational;
namespace dim = mbgc::units::dim;

Dimension parsed_dimension(const std::string& text) {
  auto p = parse_unit(text);
  EXPECT_TRUE(p.unit) << text << ": " << p.error.message;
  return p.unit ? p.unit->dimension : Dimension{};
}

double scale(const std::string& text) {
  auto p = parse_unit(text);
  EXPECT_TRUE(p.unit) << text << ": " << p.error.message;
  return p.unit ? p.unit->scale : 0.0;
}

TEST(UnitsRational, IsKeptReducedWithAPositiveDenominator) {
  EXPECT_EQ(Rational(2, 4), Rational(1, 2));
  EXPECT_EQ(Rational(3, -6), Rational(-1, 2));
  EXPECT_EQ(Rational(0, 5), Rational(0));
  EXPECT_EQ(Rational(1, 2) + Rational(1, 2), Rational(1));
  EXPECT_EQ(Rational(1, 2) * Rational(-4), Rational(-2));
}

TEST(UnitsDimension, DerivedUnitsAreTheirDefinitions) {
  EXPECT_EQ(parsed_dimension("N"), parsed_dimension("kg*m/s^2"));
  EXPECT_EQ(parsed_dimension("J"), parsed_dimension("N*m"));
  EXPECT_EQ(parsed_dimension("W"), parsed_dimension("J/s"));
  EXPECT_EQ(parsed_dimension("V"), parsed_dimension("W/A"));
  EXPECT_EQ(parsed_dimension("Ohm"), parsed_dimension("V/A"));
  EXPECT_EQ(parsed_dimension("F"), parsed_dimension("C/V"));
  EXPECT_EQ(parsed_dimension("H"), parsed_dimension("Wb/A"));
  EXPECT_EQ(parsed_dimension("S"), parsed_dimension("1/Ohm"));
  EXPECT_EQ(parsed_dimension("T"), parsed_dimension("Wb/m^2"));
  EXPECT_EQ(parsed_dimension("Pa"), parsed_dimension("N/m2"));  // 20-sim's trailing power
  EXPECT_EQ(parsed_dimension("Hz"), parsed_dimension("1/s"));
  EXPECT_EQ(parsed_dimension("N.m"), parsed_dimension("N*m"));
  EXPECT_EQ(parsed_dimension("m^(1/2)").pow(2), dim::length());
  EXPECT_EQ(parsed_dimension("s^-2"), dim::time().pow(-2));
  EXPECT_TRUE(parsed_dimension("1").is_none());
  EXPECT_TRUE(parsed_dimension("m/m").is_none());
}

TEST(UnitsDimension, EffortTimesFlowIsAPowerInEveryDomain) {
  EXPECT_EQ(dim::force() * dim::velocity(), dim::power());
  EXPECT_EQ(dim::voltage() * dim::current(), dim::power());
  EXPECT_EQ(dim::pressure() * dim::volume_flow(), dim::power());
  EXPECT_EQ(dim::temperature() * dim::entropy_flow(), dim::power());
  // a torque times an angular rate: a power once the radian is set aside
  EXPECT_NE(dim::torque() * dim::angular_velocity(), dim::power());
  EXPECT_EQ((dim::torque() * dim::angular_velocity()).without_angle(), dim::power());
  EXPECT_TRUE(dim::angle().is_angle_or_none());
  EXPECT_FALSE(dim::length().is_angle_or_none());
}

TEST(UnitsScale, PrefixesAndCommonUnitsBringAValueToSI) {
  EXPECT_DOUBLE_EQ(scale("mm"), 1e-3);
  EXPECT_DOUBLE_EQ(scale("kg"), 1.0);
  EXPECT_DOUBLE_EQ(scale("g"), 1e-3);
  EXPECT_DOUBLE_EQ(scale("kN"), 1e3);
  EXPECT_DOUBLE_EQ(scale("MPa"), 1e6);
  EXPECT_DOUBLE_EQ(scale("bar"), 1e5);
  EXPECT_DOUBLE_EQ(scale("mbar"), 100.0);
  EXPECT_DOUBLE_EQ(scale("km/h"), 1000.0 / 3600.0);
  EXPECT_DOUBLE_EQ(scale("deg"), std::numbers::pi / 180);
  EXPECT_DOUBLE_EQ(scale("rpm"), 2 * std::numbers::pi / 60);
  EXPECT_DOUBLE_EQ(scale("rev/min"), scale("rpm"));
  EXPECT_DOUBLE_EQ(scale("min"), 60.0);
  EXPECT_DOUBLE_EQ(scale("h"), 3600.0);
  EXPECT_DOUBLE_EQ(scale("L/min"), 1e-3 / 60);
  EXPECT_DOUBLE_EQ(scale("mm^2"), 1e-6);
  EXPECT_DOUBLE_EQ(scale("g*cm^2"), 1e-7);
  EXPECT_DOUBLE_EQ(scale("uF"), 1e-6);
  EXPECT_DOUBLE_EQ(scale("kOhm"), 1e3);
  EXPECT_DOUBLE_EQ(scale("ms"), 1e-3);
  EXPECT_EQ(parsed_dimension("rpm"), dim::angular_velocity());
  EXPECT_EQ(parsed_dimension("deg"), dim::angle());
  EXPECT_TRUE(parse_unit("N/m").unit->is_si());
  EXPECT_FALSE(parse_unit("deg").unit->is_si());
}

TEST(UnitsParse, ABadUnitSaysWhereAndWhatToWrite) {
  struct Case {
    const char* text;
    std::size_t at;
    const char* message;
    const char* hint;
  };
  const Case cases[] = {
      {"Nm", 0, "unknown unit `Nm`", "write N*m"},
      {"kg*foo", 3, "unknown unit `foo`", "a unit is an SI symbol"},
      {"N m", 2, "two units with only a space", "write a product with `*`"},
      {"m^", 2, "expected a power after `^`", "m^2"},
      {"1000*m", 0, "a number in a unit", "write the number in the value"},
      {"(m/s", 0, "expected `)` to close", "N/(m/s)"},
      {"", 0, "an empty unit", "{N/m}"},
      {"m%", 1, "unexpected `%`", "a unit is written with symbols"},
      {"degC", 0, "unknown unit `degC`", "write it in K"},
  };
  for (const Case& c : cases) {
    auto p = parse_unit(c.text);
    ASSERT_FALSE(p.unit) << c.text;
    EXPECT_EQ(p.error.at, c.at) << c.text;
    EXPECT_NE(p.error.message.find(c.message), std::string::npos) << c.text << ": " << p.error.message;
    EXPECT_NE(p.error.hint.find(c.hint), std::string::npos) << c.text << ": " << p.error.hint;
  }
}

TEST(UnitsFormat, ADimensionReadsAsUsersWriteIt) {
  EXPECT_EQ(format(parsed_dimension("kg*m/s^2")), "N");
  EXPECT_EQ(format(parsed_dimension("J")), "N*m");
  EXPECT_EQ(format(parsed_dimension("rpm")), "rad/s");
  EXPECT_EQ(format(parsed_dimension("N/m")), "N/m");
  EXPECT_EQ(format(parsed_dimension("1")), "1");
  EXPECT_EQ(format(parsed_dimension("kg*m^2")), "kg*m^2");
  // no name: SI base units, positive powers first
  EXPECT_EQ(format(parsed_dimension("kg/(m*s)")), "kg/(m*s)");
  EXPECT_EQ(format(parsed_dimension("m^(1/2)")), "m^(1/2)");
  EXPECT_EQ(format(parsed_dimension("1/m")), "1/m");
  // every format parses back to the same dimension
  for (const char* u : {"N*s/m", "N*m/rad", "m^3/s", "A*s^2/kg", "kg*m^2/(s^3*A)", "K/W"}) {
    std::string f = format(parsed_dimension(u));
    EXPECT_EQ(parsed_dimension(f), parsed_dimension(u)) << u << " -> " << f;
  }
}

}  // namespace
