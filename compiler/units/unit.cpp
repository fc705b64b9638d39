#include "units/unit.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

namespace mbgc::units {

Rational::Rational(long long n, long long d) : num(n), den(d) {
  if (den < 0) {
    num = -num;
    den = -den;
  }
  long long g = std::gcd(num, den);
  if (g > 1) {
    num /= g;
    den /= g;
  }
  if (num == 0) den = 1;
}

Dimension Dimension::base(Base b, Rational power) {
  Dimension d;
  d.exp_[static_cast<std::size_t>(b)] = power;
  return d;
}

bool Dimension::is_none() const {
  for (const Rational& r : exp_)
    if (!r.is_zero()) return false;
  return true;
}

bool Dimension::is_small() const {
  for (const Rational& r : exp_)
    if (!r.is_small()) return false;
  return true;
}

bool Dimension::is_angle_or_none() const { return without_angle().is_none(); }

Dimension Dimension::without_angle() const {
  Dimension d = *this;
  d.exp_[static_cast<std::size_t>(Base::Angle)] = 0;
  return d;
}

Dimension Dimension::operator*(const Dimension& o) const {
  Dimension d;
  for (std::size_t i = 0; i < kBases; ++i) d.exp_[i] = exp_[i] + o.exp_[i];
  return d;
}

Dimension Dimension::operator/(const Dimension& o) const {
  Dimension d;
  for (std::size_t i = 0; i < kBases; ++i) d.exp_[i] = exp_[i] - o.exp_[i];
  return d;
}

Dimension Dimension::pow(Rational p) const {
  Dimension d;
  for (std::size_t i = 0; i < kBases; ++i) d.exp_[i] = exp_[i] * p;
  return d;
}

namespace {

/// L^l M^m T^t I^i Θ^k N^n J^j A^a, integer exponents (the table's units).
Dimension of(int l, int m, int t, int i = 0, int k = 0, int n = 0, int j = 0, int a = 0) {
  return Dimension::base(Base::Length, l) * Dimension::base(Base::Mass, m) * Dimension::base(Base::Time, t) *
         Dimension::base(Base::Current, i) * Dimension::base(Base::Temperature, k) *
         Dimension::base(Base::Amount, n) * Dimension::base(Base::Luminosity, j) * Dimension::base(Base::Angle, a);
}

struct Symbol {
  std::string_view name;
  Dimension dimension;
  double scale;
  bool prefixes;  // takes an SI prefix (`kN`, `mm`, `MPa`)
};

const std::vector<Symbol>& symbols() {
  constexpr double pi = std::numbers::pi;
  static const std::vector<Symbol> table = {
      {"m", of(1, 0, 0), 1, true},
      {"g", of(0, 1, 0), 1e-3, true},
      {"s", of(0, 0, 1), 1, true},
      {"A", of(0, 0, 0, 1), 1, true},
      {"K", of(0, 0, 0, 0, 1), 1, true},
      {"mol", of(0, 0, 0, 0, 0, 1), 1, true},
      {"cd", of(0, 0, 0, 0, 0, 0, 1), 1, true},
      {"rad", of(0, 0, 0, 0, 0, 0, 0, 1), 1, true},
      {"N", of(1, 1, -2), 1, true},
      {"J", of(2, 1, -2), 1, true},
      {"W", of(2, 1, -3), 1, true},
      {"Pa", of(-1, 1, -2), 1, true},
      {"V", of(2, 1, -3, -1), 1, true},
      {"C", of(0, 0, 1, 1), 1, true},
      {"F", of(-2, -1, 4, 2), 1, true},
      {"H", of(2, 1, -2, -2), 1, true},
      {"Ohm", of(2, 1, -3, -2), 1, true},
      {"S", of(-2, -1, 3, 2), 1, true},
      {"Wb", of(2, 1, -2, -1), 1, true},
      {"T", of(0, 1, -2, -1), 1, true},
      {"Hz", of(0, 0, -1), 1, true},
      {"L", of(3, 0, 0), 1e-3, true},
      {"l", of(3, 0, 0), 1e-3, true},
      {"bar", of(-1, 1, -2), 1e5, true},
      {"deg", of(0, 0, 0, 0, 0, 0, 0, 1), pi / 180, false},
      {"rev", of(0, 0, 0, 0, 0, 0, 0, 1), 2 * pi, false},
      {"rpm", of(0, 0, -1, 0, 0, 0, 0, 1), 2 * pi / 60, false},
      {"min", of(0, 0, 1), 60, false},
      {"h", of(0, 0, 1), 3600, false},
  };
  return table;
}

struct Prefix {
  char symbol;
  double scale;
};
constexpr Prefix kPrefixes[] = {{'T', 1e12}, {'G', 1e9},  {'M', 1e6},  {'k', 1e3},  {'h', 1e2},  {'d', 1e-1},
                                {'c', 1e-2}, {'m', 1e-3}, {'u', 1e-6}, {'n', 1e-9}, {'p', 1e-12}};

/// `name` as a symbol, or a prefix and a symbol that takes one.
std::optional<Unit> lookup(std::string_view name) {
  for (const Symbol& s : symbols())
    if (s.name == name) return Unit{s.dimension, s.scale, std::string(name)};
  if (name.size() < 2) return std::nullopt;
  for (const Prefix& p : kPrefixes) {
    if (name[0] != p.symbol) continue;
    for (const Symbol& s : symbols())
      if (s.prefixes && s.name == name.substr(1)) return Unit{s.dimension, s.scale * p.scale, std::string(name)};
  }
  return std::nullopt;
}

/// Recursive descent over the unit's text; throws the first error.
class UnitParser {
 public:
  explicit UnitParser(std::string_view text) : text_(text) {}

  Unit parse() {
    skip_spaces();
    if (pos_ == text_.size()) fail("an empty unit", 0, "write a unit such as {m}, {N/m} or {1}");
    Unit u = product();
    if (pos_ < text_.size()) {
      if (std::isalpha(static_cast<unsigned char>(text_[pos_])))
        fail("two units with only a space between them", pos_, "write a product with `*` (or `.`), e.g. N*m");
      fail(std::string("unexpected `") + text_[pos_] + "` in the unit", pos_,
           "a unit is written with symbols, `*` or `.`, `/`, `^` and parentheses, e.g. kg*m^2 or N/(m/s)");
    }
    u.text = std::string(text_);
    return u;
  }

 private:
  [[noreturn]] void fail(std::string message, std::size_t at, std::string hint, std::size_t length = 1) {
    throw UnitError{std::move(message), at, length, std::move(hint)};
  }
  void skip_spaces() {
    while (pos_ < text_.size() && text_[pos_] == ' ') ++pos_;
  }
  bool accept(char c) {
    skip_spaces();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      skip_spaces();
      return true;
    }
    return false;
  }

  Unit product() {
    Unit u = factor();
    for (;;) {
      if (accept('*') || accept('.')) {
        Unit v = factor();
        u = {u.dimension * v.dimension, u.scale * v.scale, {}};
      } else if (accept('/')) {
        Unit v = factor();
        u = {u.dimension / v.dimension, u.scale / v.scale, {}};
      } else {
        return u;
      }
    }
  }

  Unit factor() {
    Unit u = primary();
    if (accept('^')) {
      Rational p = exponent();
      u = {u.dimension.pow(p), std::pow(u.scale, static_cast<double>(p.num) / p.den), {}};
    }
    return u;
  }

  int integer() {
    std::size_t from = pos_;
    int value = 0;
    while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) {
      if (value > 100) fail("a power too large for a unit", from, "a unit's powers are small integers");
      value = value * 10 + (text_[pos_++] - '0');
    }
    if (pos_ == from) fail("expected a power after `^`", pos_, "write e.g. m^2, s^-1 or m^(1/2)");
    skip_spaces();
    return value;
  }

  /// `2`, `-1`, `(1/2)`, `(-3/2)`
  Rational exponent() {
    if (accept('(')) {
      int sign = accept('-') ? -1 : 1;
      int num = integer();
      int den = accept('/') ? integer() : 1;
      if (den == 0) fail("a power with a zero denominator", pos_ - 1, "write e.g. m^(1/2)");
      if (!accept(')')) fail("expected `)` to close the power", pos_, "write e.g. m^(1/2)");
      return {sign * num, den};
    }
    int sign = accept('-') ? -1 : (accept('+'), 1);
    return {sign * integer()};
  }

  Unit primary() {
    skip_spaces();
    if (pos_ == text_.size()) fail("the unit ends too early", pos_ == 0 ? 0 : pos_ - 1, "complete it, e.g. N/m");
    const char c = text_[pos_];
    if (c == '(') {
      std::size_t open = pos_;
      ++pos_;
      Unit u = product();
      if (!accept(')')) fail("expected `)` to close the `(` of the unit", open, "close it, e.g. N/(m/s)");
      return u;
    }
    if (std::isdigit(static_cast<unsigned char>(c))) {
      std::size_t from = pos_;
      while (pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '.' ||
                                     text_[pos_] == 'e'))
        ++pos_;
      if (text_.substr(from, pos_ - from) != "1")
        fail("a number in a unit", from, "a unit has no factor but 1 ({1/s}); write the number in the value instead",
             pos_ - from);
      skip_spaces();
      return Unit{};
    }
    if (!std::isalpha(static_cast<unsigned char>(c)) && c != '_')
      fail(std::string("unexpected `") + c + "` in the unit", pos_, "a unit starts with a symbol such as m, kg or N, or with `(`");
    std::size_t from = pos_;
    while (pos_ < text_.size() && (std::isalpha(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) ++pos_;
    std::string_view name = text_.substr(from, pos_ - from);
    std::optional<Unit> u = lookup(name);
    if (!u) fail("unknown unit `" + std::string(name) + "`", from, unknown_hint(name), name.size());
    // 20-sim writes a power as trailing digits: m2, s2
    if (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) {
      int p = integer();
      u = Unit{u->dimension.pow(p), std::pow(u->scale, p), {}};
    }
    skip_spaces();
    return *u;
  }

  static std::string unknown_hint(std::string_view name) {
    if (name == "Nm") return "write N*m";
    if (name == "degC" || name == "celsius") return "a temperature in degrees Celsius has an offset: write it in K";
    if (name == "kph") return "write km/h";
    if (name == "ohm") return "write Ohm";
    if (name == "sec") return "write s";
    if (name == "kgf" || name == "lbf" || name == "lb" || name == "ft" || name == "in" || name == "psi")
      return "write it in SI units (m, kg, N, Pa) or with an SI prefix";
    return "a unit is an SI symbol (m, kg, s, A, K, mol, cd, rad, N, J, W, Pa, V, C, F, H, Ohm, S, Wb, T, Hz), "
           "with a prefix (mm, kN, MPa), or one of L, bar, deg, rev, rpm, min, h";
  }

  std::string_view text_;
  std::size_t pos_ = 0;
};

}  // namespace

UnitParse parse_unit(std::string_view text) {
  try {
    return {UnitParser(text).parse(), {}};
  } catch (const UnitError& e) {
    return {std::nullopt, e};
  }
}

std::vector<std::string> unit_symbols() {
  std::vector<std::string> out;
  for (const Symbol& s : symbols()) out.emplace_back(s.name);
  return out;
}

namespace dim {
Dimension length() { return of(1, 0, 0); }
Dimension mass() { return of(0, 1, 0); }
Dimension time() { return of(0, 0, 1); }
Dimension angle() { return of(0, 0, 0, 0, 0, 0, 0, 1); }
Dimension force() { return of(1, 1, -2); }
Dimension torque() { return of(2, 1, -2); }
Dimension power() { return of(2, 1, -3); }
Dimension velocity() { return of(1, 0, -1); }
Dimension angular_velocity() { return of(0, 0, -1, 0, 0, 0, 0, 1); }
Dimension voltage() { return of(2, 1, -3, -1); }
Dimension current() { return of(0, 0, 0, 1); }
Dimension pressure() { return of(-1, 1, -2); }
Dimension volume_flow() { return of(3, 0, -1); }
Dimension temperature() { return of(0, 0, 0, 0, 1); }
Dimension entropy_flow() { return of(2, 1, -3, 0, -1); }
}  // namespace dim

namespace {

/// The names a user expects for the dimensions met most in models.
const std::vector<std::pair<Dimension, std::string_view>>& named() {
  static const std::vector<std::pair<Dimension, std::string_view>> table = {
      {of(1, 0, 0), "m"},
      {of(0, 1, 0), "kg"},
      {of(0, 0, 1), "s"},
      {of(0, 0, 0, 1), "A"},
      {of(0, 0, 0, 0, 1), "K"},
      {of(0, 0, 0, 0, 0, 1), "mol"},
      {of(0, 0, 0, 0, 0, 0, 1), "cd"},
      {of(0, 0, 0, 0, 0, 0, 0, 1), "rad"},
      {of(1, 1, -2), "N"},
      {of(2, 1, -2), "N*m"},
      {of(2, 1, -3), "W"},
      {of(-1, 1, -2), "Pa"},
      {of(2, 1, -3, -1), "V"},
      {of(0, 0, 1, 1), "C"},
      {of(-2, -1, 4, 2), "F"},
      {of(2, 1, -2, -2), "H"},
      {of(2, 1, -3, -2), "Ohm"},
      {of(2, 1, -2, -1), "Wb"},
      {of(0, 0, -1), "1/s"},
      {of(0, 0, -2), "1/s^2"},
      {of(1, 0, -1), "m/s"},
      {of(1, 0, -2), "m/s^2"},
      {of(0, 0, -1, 0, 0, 0, 0, 1), "rad/s"},
      {of(0, 0, -2, 0, 0, 0, 0, 1), "rad/s^2"},
      {of(0, 1, -2), "N/m"},
      {of(0, 1, -1), "N*s/m"},
      {of(1, 1, -1), "N*s"},
      {of(2, 1, -1), "N*m*s"},
      {of(2, 1, -2, 0, 0, 0, 0, -1), "N*m/rad"},
      {of(2, 1, -1, 0, 0, 0, 0, -1), "N*m*s/rad"},
      {of(2, 1, 0), "kg*m^2"},
      {of(-3, 1, 0), "kg/m^3"},
      {of(2, 0, 0), "m^2"},
      {of(3, 0, 0), "m^3"},
      {of(3, 0, -1), "m^3/s"},
      {of(-4, 1, -1), "Pa*s/m^3"},
      {of(4, -1, 2), "m^3/Pa"},
      {of(2, 1, -3, 0, -1), "W/K"},
      {of(2, 1, -2, 0, -1), "J/K"},
  };
  return table;
}

void append_power(std::string& out, std::string_view symbol, Rational p) {
  if (!out.empty()) out += '*';
  out += symbol;
  if (p == Rational(1)) return;
  out += '^';
  if (p.den == 1) {
    out += std::to_string(p.num);
  } else {
    out += "(" + std::to_string(p.num) + "/" + std::to_string(p.den) + ")";
  }
}

}  // namespace

std::string format(const Dimension& d) {
  if (d.is_none()) return "1";
  for (const auto& [dimension, name] : named())
    if (dimension == d) return std::string(name);
  // A product of base units: the positive powers, then `/` and the negative ones.
  constexpr std::string_view kBaseSymbols[kBases] = {"m", "kg", "s", "A", "K", "mol", "cd", "rad"};
  constexpr Base kOrder[kBases] = {Base::Mass,   Base::Length, Base::Time,       Base::Current,
                                   Base::Temperature, Base::Amount, Base::Luminosity, Base::Angle};
  std::string up, down;
  for (Base b : kOrder) {
    Rational p = d[b];
    if (p.num > 0) append_power(up, kBaseSymbols[static_cast<std::size_t>(b)], p);
    if (p.num < 0) append_power(down, kBaseSymbols[static_cast<std::size_t>(b)], -p);
  }
  if (up.empty()) up = "1";
  if (down.empty()) return up;
  return up + "/" + (down.find('*') == std::string::npos ? down : "(" + down + ")");
}

namespace {
std::vector<Dimension>& literal_dimensions() {
  static std::vector<Dimension> all;
  return all;
}
}  // namespace

int literal_unit(const Dimension& d) {
  std::vector<Dimension>& all = literal_dimensions();
  auto it = std::find(all.begin(), all.end(), d);
  if (it == all.end()) it = all.insert(all.end(), d);
  return static_cast<int>(it - all.begin());
}

const Dimension& literal_dimension(int index) { return literal_dimensions().at(static_cast<std::size_t>(index)); }

}  // namespace mbgc::units
