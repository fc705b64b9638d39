// joints/free.cpp — six coordinates: B's frame moves and turns freely
// relative to A's (from ground: a floating body, such as a car's body, as
// the root of a tree in joint coordinates). A ball joint's relative rotation
// and three slides: along A's axes, or, for a body that carries others,
// B's velocity in its own axes turned into the translation. It constrains nothing, so it has no
// rows: with multipliers a floating body simply has no joint.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Free final : public JointKind {
 public:
  std::string_view name() const override { return "free"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::r0, &joint_setting::v0, &joint_setting::rot0, &joint_setting::w0}; }
  bool needs_orientation() const override { return false; }
  std::string initial_settings() const override {
    return "r0 and v0 (B's point from A's, and its velocity, in A's joint axes), rot0 (relative rotation), w0 (B's "
           "angular velocity, B's axes)";
  }
  void rows(const JointFrames& /*f*/, std::vector<E>& /*r*/) const override {}
  void mobilize(Mobilizer& m) const override {
    const E r0 = m.setting_or_default(joint_setting::r0), v0 = m.setting_or_default(joint_setting::v0);
    // A floating base that carries other bodies moves in its own joint
    // axes, as its momentum is: its articulated inertia is then the plain
    // sum of its own and its children's, with no rotation in it (the
    // two-track car's derivative: 3,150 operations become 2,891). A body
    // that flies alone keeps its translation in A's axes, where its centre's
    // flight needs nothing of its rotation (under gravity, a parabola any
    // integrator follows to rounding).
    if (!m.child_particle && m.child_carries && m.joint.a_is_parent) {
      m.ball();
      m.float_in_child_axes(r0, v0);
      return;
    }
    const char* names[3] = {"x", "y", "z"};
    const E axes[3] = {m.ex, m.ey, m.ez};
    std::vector<E> disp;
    for (int i = 0; i < 3; ++i) {
      Mobilizer::Rate& s = m.rate(m.sym.rate_junction(names[i]), names[i], m.B.at(r0, i + 1), m.B.at(v0, i + 1), false);
      s.V = axes[i];
      disp.push_back(s.value);
    }
    m.disp = m.B.list(disp);
    m.ball();
  }
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.qrel = setting_or_default(j, joint_setting::rot0, B);
    return m;
  }
};

}  // namespace

const JointKind& free_joint() {
  static const Free kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
