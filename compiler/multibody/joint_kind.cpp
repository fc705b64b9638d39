// multibody/joint_kind.cpp — what every joint kind shares, and the registry of kinds.
#include "multibody/joint_kind.hpp"

#include <map>

namespace mbgc::multibody::detail {

// The kinds, one per file under joints/.
const JointKind& cylindrical_joint();
const JointKind& distance_joint();
const JointKind& fixed_joint();
const JointKind& free_joint();
const JointKind& planar_joint();
const JointKind& prismatic_joint();
const JointKind& revolute_joint();
const JointKind& screw_joint();
const JointKind& spherical_joint();
const JointKind& universal_joint();

namespace {
const std::map<std::string, const JointKind*, std::less<>>& registry() {
  static const std::map<std::string, const JointKind*, std::less<>> kinds = [] {
    std::map<std::string, const JointKind*, std::less<>> m;
    for (const JointKind* k : {&cylindrical_joint(), &distance_joint(), &fixed_joint(), &free_joint(), &planar_joint(), &prismatic_joint(),
                               &revolute_joint(), &screw_joint(), &spherical_joint(), &universal_joint()})
      m.emplace(std::string(k->name()), k);
    return m;
  }();
  return kinds;
}
}  // namespace

const JointKind* find_joint_kind(std::string_view name) {
  auto it = registry().find(name);
  return it == registry().end() ? nullptr : it->second;
}

std::vector<std::string> joint_kind_names() {
  std::vector<std::string> names;
  for (const auto& [name, kind] : registry()) names.push_back(name);
  return names;
}

// ---- rows ------------------------------------------------------------------------------
E JointFrames::perp(const E& u, const E& v) const { return B.op('*', scale, B.dot(u, v)); }

void JointFrames::point(std::vector<E>& r) const {
  for (int k = 1; k <= 3; ++k) r.push_back(B.at(d, k));
}

void JointFrames::aligned(std::vector<E>& r) const {
  r.push_back(perp(A.Z, Bf.X));
  r.push_back(perp(A.Z, Bf.Y));
}

void JointFrames::on_axis(std::vector<E>& r) const {
  r.push_back(B.dot(A.X, d));
  r.push_back(B.dot(A.Y, d));
}

E JointFrames::turned_by(const E& angle) const {
  return B.op('-', B.op('*', B.dot(A.Y, Bf.X), B.call("cos", {angle})), B.op('*', B.dot(A.X, Bf.X), B.call("sin", {angle})));
}

E JointKind::displacement(const JointFrames& f) const { return f.B.dot(f.A.Z, f.d); }

// ---- coordinates -----------------------------------------------------------------------
Mobilizer::Mobilizer(const Build& b, const Joint& j, bool child_particle)
    : B(b), joint(j), sym(j.decl->name), child_particle(child_particle), zero(b.num(0)), ex(b.vec(1, 0, 0)), ey(b.vec(0, 1, 0)),
      ez(b.vec(0, 0, 1)), disp(b.vec(0, 0, 0)), qrel(b.list({b.num(1), b.num(0), b.num(0), b.num(0)})), angle(zero),
      angle_rate(zero), axial(zero), axial_rate(zero) {}

E Mobilizer::setting_or(const Setting& s, E fallback) const { return detail::setting_or(joint, s, std::move(fallback)); }
E Mobilizer::setting_or_default(const Setting& s) const { return detail::setting_or_default(joint, s, B); }

bool Mobilizer::prescribed() const { return given(joint, joint_setting::motion); }

Mobilizer::Rate& turn_about_axis(Mobilizer& m) {
  const Build& B = m.B;
  Mobilizer::Rate& r = m.rate(m.sym.drive(), kTurnCoordinate, m.setting_or_default(joint_setting::q0),
                              m.setting_or_default(joint_setting::rate0), m.prescribed());
  r.W = m.ez;
  r.Wb = m.ez;  // a turn about z leaves z where it is
  m.angle = r.value, m.angle_rate = r.rate;
  m.qrel = B.call("quat_axis_angle", {m.ez, m.angle});
  m.rot = B.call("rot_axis_angle", {m.ez, m.angle});
  return r;
}

Mobilizer::Rate& slide_along_axis(Mobilizer& m, const Sym& junction, const Setting& q0, const Setting& rate0,
                                  bool prescribed) {
  Mobilizer::Rate& s = m.rate(junction, "s", m.setting_or_default(q0), m.setting_or_default(rate0), prescribed);
  s.V = m.ez;
  m.axial = s.value, m.axial_rate = s.rate;
  m.disp = m.B.op('*', m.ez, m.axial);
  return s;
}

// ---- initial values --------------------------------------------------------------------
InitialMotion JointKind::initial(const Build& B, const Joint& j) const {
  E zero = B.num(0);
  InitialMotion m;
  m.angle = has_angle() ? setting_or_default(j, joint_setting::q0, B) : zero;
  m.angle_rate = has_angle() ? setting_or_default(j, joint_setting::rate0, B) : zero;
  m.axial = zero, m.axial_rate = zero;
  m.qrel = B.call("quat_axis_angle", {B.vec(0, 0, 1), m.angle});
  return m;
}

}  // namespace mbgc::multibody::detail
