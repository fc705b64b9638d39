// joints/planar.cpp — B's frame slides in A's x-y plane and turns about A's z: three coordinates.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Planar final : public JointKind {
 public:
  std::string_view name() const override { return "planar"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::v0, &joint_setting::w0}; }
  std::string initial_settings() const override {
    return "v0 ([x rate, y rate, 0], A's joint axes) and w0 ([0, 0, turn rate]); it starts with the frames together";
  }
  std::vector<int> fixed_components(std::string_view key) const override {
    if (key == joint_setting::v0.name) return {3};
    if (key == joint_setting::w0.name) return {1, 2};
    return {};
  }
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.w_rel = setting_or_default(j, joint_setting::w0, B);
    m.v_rel = setting_or_default(j, joint_setting::v0, B);
    return m;
  }
  /// B's point stays in A's x-y plane and the axes stay aligned: 3 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    r.push_back(f.B.dot(f.A.Z, f.d));
    f.aligned(r);
  }
  void mobilize(Mobilizer& m) const override {
    const E v0 = m.setting_or_default(joint_setting::v0), w0 = m.setting_or_default(joint_setting::w0);
    Mobilizer::Rate& x = m.rate(m.sym.rate_junction("x"), "x", m.zero, m.B.at(v0, 1), false);
    x.V = m.ex;
    Mobilizer::Rate& y = m.rate(m.sym.rate_junction("y"), "y", m.zero, m.B.at(v0, 2), false);
    y.V = m.ey;
    Mobilizer::Rate& turn = m.rate(m.sym.turn(), "theta", m.zero, m.B.at(w0, 3), false);
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
