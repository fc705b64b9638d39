// units/unit.hpp — physical dimensions and units of measure.
//
// A Dimension is a product of powers of the seven SI base dimensions and the
// plane angle (kept apart so that `{deg}` and `{rad/s}` mean something, and
// that `exp` of an angle can be told from `sin` of one). Exponents are
// rational: `sqrt(k/m)` is a rate. A Unit is a dimension and the factor that
// turns a value written in it into SI: `{mm}` is a length times 1e-3, `{rpm}`
// an angular rate times 2*pi/60. Offsets (degrees Celsius) are not units here.
//
// `parse_unit` reads the 20-sim notation written between braces: symbols with
// SI prefixes, `*` or `.` for a product, `/` for a quotient, `^` (or trailing
// digits, `m2`) for a power, parentheses, and `1` for no dimension.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mbgc::units {

/// A rational exponent, kept reduced with a positive denominator.
struct Rational {
  long long num = 0;
  long long den = 1;
  Rational() = default;
  Rational(long long n, long long d = 1);  // NOLINT(google-explicit-constructor): 2 is an exponent
  /// Small enough that products of a few stay exact (the checker gives up past it).
  bool is_small() const { return num < 1000000 && num > -1000000 && den < 1000000; }
  bool is_zero() const { return num == 0; }
  bool operator==(const Rational&) const = default;
  Rational operator+(Rational o) const { return {num * o.den + o.num * den, den * o.den}; }
  Rational operator-(Rational o) const { return {num * o.den - o.num * den, den * o.den}; }
  Rational operator*(Rational o) const { return {num * o.num, den * o.den}; }
  Rational operator/(Rational o) const { return {num * o.den, den * o.num}; }
  Rational operator-() const { return {-num, den}; }
};

enum class Base { Length, Mass, Time, Current, Temperature, Amount, Luminosity, Angle };
inline constexpr std::size_t kBases = 8;

class Dimension {
 public:
  Dimension() = default;
  static Dimension base(Base b, Rational power = 1);
  static Dimension none() { return {}; }

  Rational operator[](Base b) const { return exp_[static_cast<std::size_t>(b)]; }
  bool is_none() const;
  /// No dimension but, perhaps, a power of angle: what `sin` accepts.
  bool is_angle_or_none() const;
  /// The same with the angle's power dropped: a torque times a rate is a power.
  Dimension without_angle() const;

  Dimension operator*(const Dimension& o) const;
  Dimension operator/(const Dimension& o) const;
  Dimension pow(Rational p) const;
  bool operator==(const Dimension&) const = default;
  /// Every exponent Rational::is_small.
  bool is_small() const;

 private:
  std::array<Rational, kBases> exp_{};
};

/// Common dimensions, by name.
namespace dim {
Dimension length();
Dimension mass();
Dimension time();
Dimension angle();
Dimension force();
Dimension torque();
Dimension power();
Dimension velocity();
Dimension angular_velocity();
Dimension voltage();
Dimension current();
Dimension pressure();
Dimension volume_flow();
Dimension temperature();
Dimension entropy_flow();
}  // namespace dim

/// How a dimension reads to a user: a name where one is usual (`N`, `N*m`,
/// `rad/s`, `N/m`, `kg*m^2`), else a product of SI base units (`kg*m^2/s^3`);
/// `1` for none.
std::string format(const Dimension& d);

/// The dimensions of the literals written with a unit (`2 {mm}`), by an
/// index that an expression's constant carries (ir::constant): the same
/// dimension has the same index for the whole run of the compiler.
int literal_unit(const Dimension& d);
const Dimension& literal_dimension(int index);

/// A unit as written, and what it means.
struct Unit {
  Dimension dimension;
  double scale = 1.0;  // SI value = written value * scale
  std::string text;    // as written, e.g. "N/m", "km/h"
  /// The unit is the coherent SI unit of its dimension (scale 1): a value in
  /// it needs no conversion.
  bool is_si() const { return scale == 1.0; }
};

/// What `parse_unit` found wrong: a message, the offending part (offset and
/// length in the text) and a hint.
struct UnitError {
  std::string message;
  std::size_t at = 0;
  std::size_t length = 1;
  std::string hint;
};

struct UnitParse {
  std::optional<Unit> unit;
  UnitError error;  // when !unit
};

UnitParse parse_unit(std::string_view text);

/// Every unit symbol `parse_unit` knows, for the docs test and hints.
std::vector<std::string> unit_symbols();

}  // namespace mbgc::units
