// joints/planar.cpp — B's frame slides in A's x-y plane and turns about A's z: three coordinates.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Planar final : public JointKind {
 public:
  std::string_view name() const override { return "planar"; }
  /// B's point stays in A's x-y plane and the axes stay aligned: 3 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    r.push_back(f.B.dot(f.A.Z, f.d));
    f.aligned(r);
  }
  void mobilize(Mobilizer& m) const override {
    Mobilizer::Rate& x = m.rate(m.joint.decl->name + ".xdot", "x", m.zero, m.zero, false);
    x.V = m.ex;
    Mobilizer::Rate& y = m.rate(m.joint.decl->name + ".ydot", "y", m.zero, m.zero, false);
    y.V = m.ey;
    Mobilizer::Rate& turn = m.rate(m.joint.decl->name + ".turn", "theta", m.zero, m.zero, false);
    turn.W = m.ez;
    m.disp = m.B.list({x.value, y.value, m.zero});
    m.qrel = m.B.call("quat_axis_angle", {m.ez, turn.value});
    m.rot = m.B.call("rot_axis_angle", {m.ez, turn.value});
  }
};

}  // namespace

const JointKind& planar_joint() {
  static const Planar kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
