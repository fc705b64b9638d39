// multibody/units.cpp — what the multibody layer states of the units of the
// values users write in its statements: a body's mass is kg, a joint's
// torque N*m, a point m, gravity m/s^2. A literal's unit is compared here,
// at its braces (`mass = 3 {m}`); a value that reads parameters or
// quantities goes to units/check (ir::ExpandedUnitCheck), which infers
// theirs. The dimensions come from the settings' tables (settings.hpp).
#include "multibody/units.hpp"

#include <fmt/format.h>

#include <map>

#include "multibody/contact_symbols.hpp"
#include "multibody/joint_kind.hpp"
#include "multibody/rewrite.hpp"
#include "multibody/setting_names.hpp"
#include "multibody/settings.hpp"
#include "units/literals.hpp"

namespace mbgc::multibody::detail {

namespace {

/// A joint's coordinate: an angle (revolute, screw, the rotation of a
/// cylindrical joint) or a length (prismatic).
std::optional<units::Dimension> coordinate(const JointKind& kind) {
  if (kind.has_angle()) return units::dim::angle();
  if (kind.has_axial()) return units::dim::length();
  return std::nullopt;
}

/// The dimension of a joint's setting: its table's, else its kind's coordinate.
std::optional<units::Dimension> joint_dimension(const Joint& j, const Setting& s) {
  if (s.dimension) return s.dimension;
  if (&s == &joint_setting::q0 || &s == &joint_setting::motion) return coordinate(*j.kind);
  if (&s == &joint_setting::rate0)
    if (auto c = coordinate(*j.kind)) return *c / units::dim::time();
  return std::nullopt;
}

}  // namespace

namespace {

/// The dimensions of the quantities the layer defines, by their last part
/// (a point's `tip.position` as a body's `position`), a tyre's signals too.
const std::map<std::string, units::Dimension>& quantity_dimensions() {
  using namespace units::dim;
  static const std::map<std::string, units::Dimension> kQuantities = {
      {"position", length()},
      {"velocity", velocity()},
      {"momentum", force() * units::dim::time()},
      {"quaternion", units::Dimension::none()},
      {"rotation", units::Dimension::none()},
      {"bryant", angle()},
      {"omega", angular_velocity()},
      {"omega_world", angular_velocity()},
      {"angular_momentum", torque() * units::dim::time()},
      {"kinetic_energy", torque()},
      {"potential_energy", torque()},
      {"angle", angle()},
      {"rate", angular_velocity()},
      {"displacement", length()},
      {"displacement_rate", velocity()},
      {"gap", length()},
      {"normal_force", force()},
      {"friction_force", force()},
      {"slip_velocity", velocity()},
      {"torque", torque()},
      {"length", length()},
      {"normal", units::Dimension::none()},
      // a tyre's (docs/language.md, section 9)
      {"Fx", force()},
      {"Fy", force()},
      {"Fz", force()},
      {"Fx0", force()},
      {"Fy0", force()},
      {"Dx", force()},
      {"Dy", force()},
      {"Kx", force()},
      {"Ky", force() / angle()},
      {"contact_point", length()},
      {"power", torque() / units::dim::time()},
      {"slip_ratio", units::Dimension::none()},
      {"slip_angle", angle()},
      {"alpha_y", angle()},
      {"kappa_x", units::Dimension::none()},
      {"deflection", length()},
      {"centre_height", length()},
      {"forward", units::Dimension::none()},
      {"left", units::Dimension::none()},
      {"Vcx", velocity()},
      {"Vcy", velocity()},
      {"Vsx", velocity()},
      {"spin", angular_velocity()},
      {"sigma_kappa", length()},
      {"sigma_alpha", length()},
      {"dfz", units::Dimension::none()},
      {"mu_y", units::Dimension::none()},
      {"Gx", units::Dimension::none()},
      {"Gy", units::Dimension::none()},
      {"road_height", length()},
      {"road_slope", units::Dimension::none()},
  };
  return kQuantities;
}

/// The dimension of the quantity `name` (quantity_dimensions); none: not stated.
std::optional<units::Dimension> quantity_dimension(const std::string& name) {
  const std::map<std::string, units::Dimension>& kQuantities = quantity_dimensions();
  auto dot = name.rfind('.');
  auto it = kQuantities.find(name.substr(dot == std::string::npos ? 0 : dot + 1));
  if (it == kQuantities.end()) return std::nullopt;
  return it->second;
}

}  // namespace

std::vector<ir::ExpandedUnitCheck> state_units(const Model& m, const Quantities& quantities,
                                               const std::set<std::string>& used, SymbolIds& symbols,
                                               ir::Diagnostics& diags) {
  std::vector<ir::ExpandedUnitCheck> out;
  // the settings' values are rewritten as the user's statements were; what they read is not stated again
  QuantityRewriter rewrite(quantities, m, diags);
  // that the value of setting `a` (`what`) has `dimension` (none: nothing is stated)
  auto state_unit = [&](const ir::AstAttr& a, const std::optional<units::Dimension>& dimension, const std::string& what) {
    if (!dimension || !a.value) return;
    // the literals' units, each where it is written
    const bool wrong = !units::check_literal_units(*a.value, *dimension, what, diags);
    if (!wrong && units::reads_a_name(*a.value)) out.push_back({rewrite.expr(term(a.value)), *dimension, a.loc, what});
  };
  // what the user's expressions read of the bodies and joints (`arm.tip.position` is m)
  for (const std::string& name : used)
    if (auto d = quantity_dimension(name)) {
      const E& value = quantities.at(name);
      out.push_back({value, *d, value->loc, fmt::format("`{}`", name), true});
    }
  for (const auto& [name, body] : m.bodies) {
    if (!body.decl) continue;
    const std::vector<const Setting*>& table = body.kind.field() ? body.kind.field()->settings() : body_setting::kAll;
    for (const ir::AstAttr& a : body.decl->attrs) {
      const Setting* s = find_setting(table, a.key);
      if (!s) continue;
      const std::string what = fmt::format("{} of body `{}`", a.key, name);
      if (s == &beam_setting::section && a.value && a.value->kind == ir::AstExpr::Kind::Call)  // each dimension a length
        for (const auto& x : a.value->args)
          state_unit(ir::AstAttr{a.key, x->loc, x}, s->dimension, what);
      else state_unit(a, s->dimension, what);
    }
    for (const ir::AstPoint& p : body.decl->points)
      state_unit(ir::AstAttr{p.name, p.loc, p.value}, units::dim::length(), fmt::format("point `{}` of `{}`", p.name, name));
  }
  for (const Joint& j : m.joints)
    for (const auto& [key, a] : j.attrs)
      if (const Setting* s = find_setting(joint_setting::kAll, key))
        state_unit(*a, joint_dimension(j, *s), fmt::format("{} of joint `{}`", key, j.decl->name));
  for (const Contact& c : m.contacts)
    for (const auto& [key, a] : c.attrs)
      if (const Setting* s = find_setting(contact_setting::kAll, key))
        state_unit(*a, s->dimension, fmt::format("{} of contact `{}`", key, c.decl->name));
  for (const ForceElement& f : m.forces)
    for (const auto& [key, a] : f.attrs)
      if (const Setting* s = find_setting(force_setting::kAll, key))
        state_unit(*a, s->dimension, fmt::format("{} of force `{}`", key, f.decl->name));
  for (const Tyre& t : m.tyres) {
    for (const auto& [key, a] : t.attrs)
      state_unit(*a, tyre_setting_dimension(key), fmt::format("{} of tyre `{}`", key, t.decl->name));
    // its quantities are signals it writes (`tyre1.Fz`), which the check does not read: their units are stated
    const TyreSym tyre(t.decl->name);
    for (const auto& [q, d] : quantity_dimensions())
      if (const Sym s = tyre.signal(q); quantities.is_generated(s.str()))
        out.push_back({Build(t.decl->loc, symbols).ref(s), d, t.decl->loc, fmt::format("`{}`", s.str()), true});
  }
  if (m.gravity) state_unit(ir::AstAttr{"gravity", m.gravity_loc, m.gravity}, units::dim::velocity() / units::dim::time(),
                           "gravity");
  return out;
}

}  // namespace mbgc::multibody::detail
