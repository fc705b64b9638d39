// joints/distance.cpp — a massless rod: two points kept `length` apart.
#include <fmt/format.h>

#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Distance final : public JointKind {
 public:
  std::string_view name() const override { return "distance"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::length}; }
  std::vector<const Setting*> required() const override { return {&joint_setting::length}; }
  bool has_displacement() const override { return true; }
  bool needs_orientation() const override { return false; }
  bool moves_particles() const override { return true; }
  std::string initial_settings() const override { return "axis (the direction of the rod from the first point)"; }
  void check_constant(const ir::AstJoint& j, const ir::AstAttr& at, double v, ir::Diagnostics& diags) const override {
    if (at.key == joint_setting::length.name && !(v > 0))
      diags.error(at.value->loc, fmt::format("the length of distance joint `{}` is {}", j.name, v),
                  "a distance joint keeps two points `length` apart and must be positive; points that coincide are a "
                  "spherical joint: write joint " + j.name + " spherical(...)");
  }
  void params(const Joint& j, const std::function<void(const Sym&, E)>& param) const override {
    param(JointSym(j.decl->name).length(), term(given_attr(j, joint_setting::length)->value));
  }
  /// (|d|^2 - L^2) / (2 L): one row, in metres.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    const Build& B = f.B;
    E L = B.ref(f.sym().length());
    r.push_back(B.op('/', B.op('-', B.dot(f.d, f.d), B.op('^', L, B.num(2))), B.op('*', B.num(2), L)));
  }
  E displacement(const JointFrames& f) const override { return f.B.call("norm", {f.d}); }
  /// The rod's direction: two angles as a universal joint's (about A's x,
  /// then the turned y); the rod starts along A's z, the joint axis. B's
  /// point moves by d = L R(alpha, beta) z; its rates are w x d. Behind the
  /// rod a body turns freely, as on a ball joint.
  void mobilize(Mobilizer& m) const override {
    const Build& B = m.B;
    Mobilizer::Rate& a = m.rate(m.sym.rate_junction("alpha"), "alpha", m.zero, m.zero, false);
    Mobilizer::Rate& b = m.rate(m.sym.rate_junction("beta"), "beta", m.zero, m.zero, false);
    E qa = B.call("quat_axis_angle", {m.ex, a.value});
    E arm_b = B.op('*', B.call("rotq", {qa}), m.ey);
    E turned = B.call("quat_mul", {qa, B.call("quat_axis_angle", {m.ey, b.value})});
    m.disp = B.op('*', B.op('*', B.call("rotq", {turned}), m.ez), B.ref(m.sym.length()));
    a.V = B.call("cross", {m.ex, m.disp});
    b.V = B.call("cross", {arm_b, m.disp});
    m.axial = B.ref(m.sym.length());  // `j.displacement`
    if (!m.child_particle) m.ball();
  }
  /// The rod starts along the joint axis.
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.axial = B.ref(JointSym(j.decl->name).length());
    return m;
  }
};

}  // namespace

const JointKind& distance_joint() {
  static const Distance kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
