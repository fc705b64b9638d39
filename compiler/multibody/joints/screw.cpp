// joints/screw.cpp — rotation about the joint axis that advances `pitch` metres per radian along it.
#include <fmt/format.h>

#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Screw final : public JointKind {
 public:
  std::string_view name() const override { return "screw"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::q0, &joint_setting::rate0, &joint_setting::torque, &joint_setting::motion, &joint_setting::pitch}; }
  std::vector<const Setting*> required() const override { return {&joint_setting::pitch}; }
  bool has_angle() const override { return true; }
  bool has_axial() const override { return true; }
  std::string initial_settings() const override { return "q0 (angle) and rate0"; }
  void check_constant(const ir::AstJoint& j, const ir::AstAttr& at, double v, ir::Diagnostics& diags) const override {
    if (at.key == joint_setting::pitch.name && v == 0)
      diags.error(at.value->loc, fmt::format("the pitch of screw joint `{}` is 0", j.name),
                  "a screw advances `pitch` metres per radian; with no advance it is a revolute joint: write joint " +
                      j.name + " revolute(...)");
  }
  void params(const Joint& j, const std::function<void(const Sym&, E)>& param) const override {
    param(JointSym(j.decl->name).pitch(), term(given_attr(j, joint_setting::pitch)->value));
  }
  /// On the axis, aligned, and the slide s = pitch * theta, written without
  /// atan2 (no wrap): pitch * sin(theta - s / pitch) = 0. 5 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    f.on_axis(r);
    f.aligned(r);
    E h = f.B.ref(f.sym().pitch());
    E phase = f.B.op('/', f.B.dot(f.A.Z, f.d), h);
    r.push_back(f.B.op('*', h, f.turned_by(phase)));
  }
  void mobilize(Mobilizer& m) const override {
    Mobilizer::Rate& r = turn_about_axis(m);
    E h = m.B.ref(m.sym.pitch());
    r.V = m.B.op('*', h, m.ez);
    m.axial = m.B.op('*', h, m.angle), m.axial_rate = m.B.op('*', h, m.angle_rate);
    m.disp = m.B.op('*', m.ez, m.axial);
  }
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    const E h = B.ref(JointSym(j.decl->name).pitch());
    m.axial = B.op('*', h, m.angle);
    m.axial_rate = B.op('*', h, m.angle_rate);
    return m;
  }
};

}  // namespace

const JointKind& screw_joint() {
  static const Screw kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
