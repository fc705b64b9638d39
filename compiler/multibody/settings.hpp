// multibody/settings.hpp — a setting of a multibody statement, declared once:
// its name, its default, the shape its value must have and how to write it,
// whether its value must be known before the run, and its dimension. The
// joint settings are here: the common ones every joint takes, and those the
// joint kinds list (JointKind::settings); and a rigid body's, a force
// element's, a contact's, a tyre's, a beam's and a modal body's. Parsing
// (collect.cpp), the joint kinds, the code that reads a setting or applies
// its default, and the language reference's test all name a setting through
// these entries, never by its spelling.
#pragma once

#include <charconv>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "units/unit.hpp"

namespace mbgc::multibody::detail {

/// Rows and columns of a value, when they can be told from the text alone.
struct Shape {
  int rows = 1, cols = 1;
  bool operator==(const Shape& o) const { return rows == o.rows && cols == o.cols; }
  bool scalar() const { return rows == 1 && cols == 1; }
  std::string text() const {
    if (scalar()) return "a scalar";
    if (cols == 1) return fmt::format("a {}-vector", rows);
    return fmt::format("a {}x{} matrix", rows, cols);
  }
};

/// What a body or joint setting must be, and how to write it.
struct Expected {
  Shape shape;
  const char* how;
};

/// What a setting is when it is not given, declared with the setting: a
/// value, written as the language writes it ("0.3", "[1, 0, 0, 0]", "on"),
/// which the code that applies it reads from here; or, where no one value
/// stands for it, what does ("required", "from the mode sets").
struct Default {
  const char* value = nullptr;
  const char* otherwise = nullptr;
  /// The value's numbers: one for a number, one per item of a list; none
  /// for a word or where there is no value.
  std::vector<double> numbers() const {
    std::vector<double> out;
    const std::string_view text(value ? value : "");
    if (text.empty()) return out;
    const bool list = text.front() == '[';
    std::size_t i = list ? 1 : 0;
    const std::size_t end = list ? text.find(']') : text.size();
    if (end == std::string_view::npos) return out;
    while (i < end) {
      while (i < end && (text[i] == ' ' || text[i] == ',')) ++i;
      if (i == end) break;
      double x = 0;
      auto [next, error] = std::from_chars(text.data() + i, text.data() + end, x);
      if (error != std::errc()) return {};  // a word
      out.push_back(x);
      i = static_cast<std::size_t>(next - text.data());
    }
    return out;
  }
  /// The value as one number; it must be one.
  double number() const {
    const std::vector<double> x = numbers();
    if (x.size() != 1) throw std::logic_error(fmt::format("the default `{}` is not a number", value ? value : "(none)"));
    return x[0];
  }
};
/// A setting's default value, as the language writes it.
constexpr Default defaults_to(const char* value) { return {value, nullptr}; }
/// A setting without a default value: `instead` says what stands for it.
constexpr Default no_default(const char* instead) { return {nullptr, instead}; }

struct Setting {
  const char* name;
  /// Its value when not given, or what stands for it.
  Default by_default;
  /// The shape of its value, checked where the text shows it; none: a word
  /// (`constraint = lagrange`) or a value its reader checks.
  std::optional<Expected> expected;
  /// Its value must be known before the run; false: a function of t or of
  /// the state (a drive's torque, a prescribed motion).
  bool constant = true;
  /// The dimension of its value (checked against the units the model
  /// declares); none: a number, or one its joint kind decides (`q0` is an
  /// angle of a revolute joint, a length of a prismatic one).
  std::optional<units::Dimension> dimension = std::nullopt;
  /// What it is and how it is written, for a diagnostic that asks for it
  /// (a flexible body's settings).
  const char* what = nullptr;
};

namespace joint_setting {
inline const Setting axis{"axis", defaults_to("[0, 0, 1]"),
                          Expected{{3, 1}, "an axis is a direction [x, y, z] in the frames of both bodies"}, true, units::Dimension::none()};
inline const Setting axis_a{"axis_a", no_default("`axis`"),
                            Expected{{3, 1}, "an axis is a direction [x, y, z] in the first body's frame"}, true, units::Dimension::none()};
inline const Setting axis_b{"axis_b", no_default("`axis`"),
                            Expected{{3, 1}, "an axis is a direction [x, y, z] in the second body's frame"}, true, units::Dimension::none()};
inline const Setting constraint{"constraint", no_default("the model's strategy (`constraints`, `mbgc --constraints`)"), std::nullopt};
inline const Setting stiffness{"stiffness", no_default("1e6 times the lighter body's mass"), Expected{{1, 1}, "the penalty stiffness is a scalar"}};
inline const Setting damping{"damping", no_default("critical: 2 sqrt(m stiffness)"), Expected{{1, 1}, "the penalty damping is a scalar"}};
inline const Setting stabilisation{"stabilisation", defaults_to("20"), std::nullopt, true, units::dim::time().pow(-1)};
inline const Setting rot0{"rot0", defaults_to("[1, 0, 0, 0]"),
                          Expected{{4, 1}, "the initial relative rotation is a quaternion [w, x, y, z], e.g. "
                                           "quat_axis_angle([0, 0, 1], 0.5)"}, true, units::Dimension::none()};
inline const Setting r0{"r0", defaults_to("[0, 0, 0]"),
                        Expected{{3, 1}, "the initial position of the second point from the first is a 3-vector "
                                         "in the first body's joint axes"}, true, units::dim::length()};
inline const Setting v0{"v0", defaults_to("[0, 0, 0]"),
                        Expected{{3, 1}, "the initial velocity of the second point relative to the first is a "
                                         "3-vector in the first body's joint axes"}, true, units::dim::velocity()};
inline const Setting w0{"w0", defaults_to("[0, 0, 0]"),
                        Expected{{3, 1}, "the initial relative angular velocity is a 3-vector in the second "
                                         "body's axes (rad/s)"}, true, units::dim::angular_velocity()};
inline const Setting q0{"q0", defaults_to("0"), Expected{{1, 1}, "the initial joint coordinate is a scalar, e.g. q0 = 0.3"}};
inline const Setting rate0{"rate0", defaults_to("0"), Expected{{1, 1}, "the initial joint rate is a scalar, e.g. rate0 = 0"}};
inline const Setting d0{"d0", defaults_to("0"),
                        Expected{{1, 1}, "the initial axial displacement is a scalar, e.g. d0 = 0.1"}, true, units::dim::length()};
inline const Setting ddot0{"ddot0", defaults_to("0"), Expected{{1, 1}, "the initial axial rate is a scalar"}, true, units::dim::velocity()};
inline const Setting pitch{"pitch", no_default("required"),
                           Expected{{1, 1}, "the pitch is a scalar (m per rad)"}, true, units::dim::length() / units::dim::angle()};
inline const Setting length{"length", no_default("required"), Expected{{1, 1}, "the length is a scalar (m)"}, true, units::dim::length()};
inline const Setting torque{"torque", no_default("none: no drive"),
                            Expected{{1, 1}, "the drive torque about the joint axis is a scalar (N m)"}, false, units::dim::torque()};
inline const Setting force{"force", no_default("none: no drive"),
                           Expected{{1, 1}, "the drive force along the joint axis is a scalar (N)"}, false, units::dim::force()};
inline const Setting motion{"motion", no_default("none: the joint moves freely"),
                            Expected{{1, 1}, "a prescribed motion is a scalar function of t, e.g. motion = "
                                                       "0.5 * sin(t)"},
                            false};

/// The settings every joint takes, in the order diagnostics list them
/// before its kind's own.
inline const std::vector<const Setting*> kCommon = {&axis, &axis_a, &axis_b, &constraint, &stiffness, &damping,
                                                    &stabilisation};
/// Every joint setting: the common ones, then the kinds' own.
inline const std::vector<const Setting*> kAll = {&axis,  &axis_a, &axis_b, &constraint, &stiffness, &damping,
                                                 &stabilisation, &rot0, &r0, &v0, &w0, &q0, &rate0, &d0, &ddot0,
                                                 &pitch, &length, &torque, &force, &motion};
}  // namespace joint_setting

/// A rigid body's settings; a flexible body's initial values are these too.
namespace body_setting {
inline const Setting mass{"mass", no_default("required"), Expected{{1, 1}, "the mass is a scalar (kg), e.g. mass = 2"}, true, units::dim::mass()};
inline const Setting inertia{"inertia", no_default("none: a particle"),
                             Expected{{3, 3}, "the inertia tensor about the centre of mass, in body axes, is a 3x3 matrix, e.g. "
                                              "inertia = diag(Jx, Jy, Jz)"},
                             true, units::dim::mass() * units::dim::length().pow(2)};
inline const Setting com{"com", defaults_to("[0, 0, 0]"),
                         Expected{{3, 1}, "the centre of mass is a body-frame position [x, y, z]"}, true,
                         units::dim::length()};
inline const Setting r0{"r0", defaults_to("[0, 0, 0]"),
                        Expected{{3, 1}, "the initial position of the centre of mass is [x, y, z] (world frame)"}, true,
                        units::dim::length()};
inline const Setting quat0{"quat0", defaults_to("[1, 0, 0, 0]"),
                           Expected{{4, 1}, "the initial orientation is a quaternion [w, x, y, z], e.g. "
                                            "quat_axis_angle([0, 0, 1], 0.3)"},
                           true, units::Dimension::none()};
inline const Setting v0{"v0", defaults_to("[0, 0, 0]"),
                        Expected{{3, 1}, "the initial velocity of the centre of mass is [vx, vy, vz] (world frame)"},
                        true, units::dim::velocity()};
inline const Setting w0{"w0", defaults_to("[0, 0, 0]"),
                        Expected{{3, 1}, "the initial angular velocity is [wx, wy, wz] (body frame)"}, true,
                        units::dim::angular_velocity()};
inline const Setting shape{"shape", no_default("a box around the points and the centre of mass; a particle: a ball"), std::nullopt};
inline const std::vector<const Setting*> kAll = {&mass, &inertia, &com, &r0, &quat0, &v0, &w0, &shape};
}  // namespace body_setting

/// A force element's settings: loads on the second point (their opposite on
/// the first), world axes, and a spring-damper along the line between them.
namespace force_setting {
inline const Setting force{"force", defaults_to("[0, 0, 0]"), std::nullopt, false, units::dim::force()};
inline const Setting torque{"torque", no_default("none"), std::nullopt, false, units::dim::torque()};
inline const Setting stiffness{"stiffness", no_default("none: no spring"), std::nullopt, true, units::dim::force() / units::dim::length()};
inline const Setting damping{"damping", no_default("none: no damper"), std::nullopt, true, units::dim::force() / units::dim::velocity()};
inline const Setting length{"length", no_default("none; needed with `stiffness`"), std::nullopt, true, units::dim::length()};
inline const std::vector<const Setting*> kAll = {&force, &torque, &stiffness, &damping, &length};
}  // namespace force_setting

/// A contact's settings; `surface` and `strategy` are words, `vertices` is
/// checked with its surface.
namespace contact_setting {
inline const Setting radius{"radius", defaults_to("0"),
                            Expected{{1, 1}, "the radius of the sphere around the touching point is a scalar "
                                             "(m); 0: the point itself"},
                            true, units::dim::length()};
inline const Setting surface{"surface", defaults_to("plane"), std::nullopt};
inline const Setting normal{"normal", no_default("required for a plane"),
                            Expected{{3, 1}, "a plane's outward normal is a direction [x, y, z] in the "
                                             "surface body's frame"},
                            true, units::Dimension::none()};
inline const Setting axis{"axis", no_default("required for a cylinder"),
                          Expected{{3, 1}, "a cylinder's axis is a direction [x, y, z] in the surface body's frame"},
                          true, units::Dimension::none()};
inline const Setting surface_radius{"surface_radius", no_default("required for a sphere or cylinder"),
                                    Expected{{1, 1}, "the radius of the surface's sphere or cylinder is a scalar (m)"},
                                    true, units::dim::length()};
inline const Setting vertices{"vertices", no_default("required for a polygon"), std::nullopt, true, units::dim::length()};
inline const Setting strategy{"strategy", no_default("unilateral, or what `mbgc --contacts` says"), std::nullopt};
inline const Setting restitution{"restitution", defaults_to("0"),
                                 Expected{{1, 1}, "the coefficient of restitution is a scalar in [0, 1]"},
                                 true, units::Dimension::none()};
/// N/m^exponent: its dimension depends on the exponent
inline const Setting stiffness{"stiffness", no_default("required for a compliant contact"),
                               Expected{{1, 1}, "the contact stiffness is a scalar (N/m^exponent)"}};
inline const Setting exponent{"exponent", defaults_to("1.5"),
                              Expected{{1, 1}, "the force exponent is a scalar (1.5: Hertz)"}, true,
                              units::Dimension::none()};
inline const Setting friction{"friction", no_default("none: no friction"),
                              Expected{{1, 1}, "the friction coefficient is a scalar >= 0"}, true,
                              units::Dimension::none()};
inline const Setting slip_speed{"slip_speed", defaults_to("1e-4"),
                                Expected{{1, 1}, "the slip speed of regularised friction is a scalar "
                                                 "(m/s)"},
                                true, units::dim::velocity()};
inline const Setting stabilisation{"stabilisation", defaults_to("20"),
                                   Expected{{1, 1}, "the stabilisation is a scalar (rad/s)"}, true,
                                   units::dim::time().pow(-1)};
inline const std::vector<const Setting*> kAll = {&radius,   &surface,     &normal,    &axis,     &surface_radius,
                                                 &vertices, &strategy,    &restitution, &stiffness, &exponent,
                                                 &friction, &slip_speed, &stabilisation};
}  // namespace contact_setting

/// A tyre's settings besides the Magic Formula's coefficients (their table:
/// tyres.cpp, kTyreSettings).
namespace tyre_setting {
inline const Setting axis{"axis", defaults_to("[0, 1, 0]"),
                          Expected{{3, 1}, "the wheel's axle is a direction [x, y, z] in the wheel's frame, e.g. "
                                           "axis = [0, 1, 0]"},
                          true, units::Dimension::none()};
/// [[x1, h1], ...]: checked by its reader
inline const Setting profile{"profile", no_default("a flat road, h = 0"), std::nullopt, true, units::dim::length()};
inline const std::vector<const Setting*> kAll = {&axis, &profile};
}  // namespace tyre_setting

/// A beam's settings (`flexible = beam`), each with what it is.
namespace beam_setting {
using units::Dimension;
namespace d = units::dim;
inline const Setting flexible{"flexible", no_default("required"), std::nullopt, true, std::nullopt, "beam"};
inline const Setting length{"length", no_default("required"),
                            std::nullopt, true, d::length(), "the beam's length (m), a number or constant parameter"};
inline const Setting density{"density", no_default("required"), std::nullopt, true, d::mass() / d::length().pow(3), "the material density (kg/m^3)"};
inline const Setting E{"E", no_default("required"), std::nullopt, true, d::force() / d::length().pow(2), "Young's modulus (Pa)"};
/// rectangle(width_y, height_z), circle(diameter), tube(outer, inner): each argument is a length
inline const Setting section{"section", no_default("required, or `area`, `Iy` and `Iz`"), std::nullopt, true, d::length(),
                             "rectangle(width_y, height_z), circle(diameter) or tube(outer, inner) (m)"};
inline const Setting area{"area", no_default("required without `section`"),
                          std::nullopt, true, d::length().pow(2), "the section area (m^2), with Iy and Iz instead of `section`"};
inline const Setting Iy{"Iy", no_default("required without `section`"), std::nullopt, true, d::length().pow(4),
                        "the second moment of area about the body y axis (m^4): bending in the x-z plane"};
inline const Setting Iz{"Iz", no_default("required without `section`"), std::nullopt, true, d::length().pow(4),
                        "the second moment of area about the body z axis (m^4): bending in the x-y plane"};
inline const Setting modes_xy{"modes_xy", no_default("none; at least one mode set is required"),
                              std::nullopt, true, std::nullopt, "the mode set of bending in the x-y plane, e.g. clamped_free(3)"};
inline const Setting modes_xz{"modes_xz", no_default("none; at least one mode set is required"),
                              std::nullopt, true, std::nullopt, "the mode set of bending in the x-z plane, e.g. pinned_pinned(2)"};
inline const Setting modes_axial{"modes_axial", no_default("none; at least one mode set is required"),
                                 std::nullopt, true, std::nullopt, "the mode set of stretch along x, e.g. fixed_free(2)"};
inline const Setting modes_torsion{"modes_torsion", no_default("none; at least one mode set is required"),
                                   std::nullopt, true, std::nullopt, "the mode set of twist about x, e.g. fixed_free(1)"};
inline const Setting G{"G", no_default("required with `modes_torsion`"),
                       std::nullopt, true, d::force() / d::length().pow(2), "the shear modulus (Pa), for torsion"};
inline const Setting torsion_constant{"torsion_constant", no_default("from `section`"), std::nullopt, true, d::length().pow(4),
                                      "the section's torsion constant (m^4); circle and tube: the polar moment, rectangle: "
                                      "Roark's formula"};
inline const Setting damping{"damping", defaults_to("0"), std::nullopt, true, Dimension::none(),
                             "the modal damping ratio (0.01 = 1 % of critical in every mode)"};
inline const Setting geometric_stiffness{"geometric_stiffness", defaults_to("on"), std::nullopt, true, std::nullopt, "on or off"};
inline const Setting slope_limit{"slope_limit", defaults_to("0.3"), std::nullopt, true, d::angle(),
                                 "the largest slope (rad) one mode may give the beam before the run stops"};
inline const Setting frame{"frame", no_default("from the mode sets: `joint`, or `buckens` when every set is free_free"),
                           std::nullopt, true, std::nullopt,
                           "joint (fixed to the beam at x = 0), centre (to its centre section), buckens or tisserand (mean "
                           "axes of free-free modes)"};
inline const std::vector<const Setting*> kAll = {&flexible, &length,   &density,  &E,        &section,          &area,
                                                 &Iy,       &Iz,       &modes_xy, &modes_xz, &modes_axial,      &modes_torsion,
                                                 &G,        &torsion_constant, &damping, &geometric_stiffness, &slope_limit,
                                                 &frame,    &body_setting::r0, &body_setting::quat0, &body_setting::v0,
                                                 &body_setting::w0};
}  // namespace beam_setting

/// A body read from a modal-data file (`flexible = modal("file.mbm")`): the
/// file gives its mass, stiffness and nodes, the model what is left.
namespace modal_setting {
inline const Setting stiffness_scale{"stiffness_scale", defaults_to("1"), std::nullopt, true, units::Dimension::none(),
                                     "a factor on the file's modal stiffness"};
inline const std::vector<const Setting*> kAll = {&beam_setting::flexible, &beam_setting::damping, &beam_setting::slope_limit,
                                                 &stiffness_scale,        &body_setting::r0,      &body_setting::quat0,
                                                 &body_setting::v0,       &body_setting::w0};
}  // namespace modal_setting

/// The setting of `table` named `key`, or null.
inline const Setting* find_setting(const std::vector<const Setting*>& table, const std::string& key) {
  for (const Setting* s : table)
    if (key == s->name) return s;
  return nullptr;
}

/// A statement's setting `s`, from its settings by name (`attrs`: a body's,
/// a contact's, ...): null where not given.
template <class Map>
inline auto given_in(const Map& attrs, const Setting& s) -> typename Map::mapped_type {
  auto it = attrs.find(s.name);
  return it == attrs.end() ? nullptr : it->second;
}

/// The names of `settings`, in their order.
inline std::vector<std::string> setting_names(const std::vector<const Setting*>& settings) {
  std::vector<std::string> out;
  for (const Setting* s : settings) out.emplace_back(s->name);
  return out;
}

}  // namespace mbgc::multibody::detail
