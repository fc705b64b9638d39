// joints/universal.cpp — a Hooke joint: a cross whose arms are A's x and B's y; two coordinates.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Universal final : public JointKind {
 public:
  std::string_view name() const override { return "universal"; }
  /// The points coincide and the arms stay perpendicular: 4 rows. The
  /// cross's arms are A's x and B's y: perpendicular when the joint frames
  /// coincide (as the tree placement puts them), free to turn about either
  /// arm; the twist about the shafts (the frames' z) is forbidden.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    f.point(r);
    r.push_back(f.perp(f.A.X, f.Bf.Y));
  }
  /// About A's x (the cross's first arm), then about the turned y (B's y).
  void mobilize(Mobilizer& m) const override {
    const Build& B = m.B;
    Mobilizer::Rate& a = m.rate(m.joint.decl->name + ".alphadot", "alpha", m.zero, m.zero, false);
    a.W = m.ex;
    Mobilizer::Rate& b = m.rate(m.joint.decl->name + ".betadot", "beta", m.zero, m.zero, false);
    E qa = B.call("quat_axis_angle", {m.ex, a.value});
    E Ra = B.call("rot_axis_angle", {m.ex, a.value});
    b.W = B.op('*', Ra, m.ey);
    // in B's axes (R = Ra Rb): the second arm is B's y; the first is Rb^T x
    a.Wb = B.op('*', B.call("transpose", {B.call("rot_axis_angle", {m.ey, b.value})}), m.ex);
    b.Wb = m.ey;
    m.qrel = B.call("quat_mul", {qa, B.call("quat_axis_angle", {m.ey, b.value})});
    m.rot = B.op('*', Ra, B.call("rot_axis_angle", {m.ey, b.value}));
  }
};

}  // namespace

const JointKind& universal_joint() {
  static const Universal kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
