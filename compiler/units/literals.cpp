#include "units/literals.hpp"

#include <fmt/format.h>

namespace mbgc::units {

using ir::AstExpr;

bool check_literal_units(const AstExpr& value, const Dimension& dimension, const std::string& what, ir::Diagnostics& diags) {
  bool ok = true;
  if (value.kind == AstExpr::Kind::Number && value.unit &&
      !(value.unit->unit.dimension.without_angle() == dimension.without_angle())) {
    const bool number = dimension.is_none();  // a coefficient, a ratio
    diags.error(value.unit->loc,
                fmt::format("the {} is {}, and {{{}}} is {}", what, number ? "a number" : format(dimension),
                            value.unit->unit.text, format(value.unit->unit.dimension)),
                number ? std::string("write it without a unit (or {1})")
                       : fmt::format("write it in {} (or in a unit of the same dimension)", format(dimension)));
    ok = false;
  }
  const bool entries = value.kind == AstExpr::Kind::List || value.kind == AstExpr::Kind::Unary ||
                       (value.kind == AstExpr::Kind::Call && value.name == "diag");
  if (entries)
    for (const auto& x : value.args)
      if (x && !check_literal_units(*x, dimension, what, diags)) ok = false;
  return ok;
}

bool reads_a_name(const AstExpr& e) {
  if (e.kind == AstExpr::Kind::Name) return true;
  for (const auto& a : e.args)
    if (a && reads_a_name(*a)) return true;
  return false;
}

}  // namespace mbgc::units
