// joints/universal.cpp — a Hooke joint: a cross whose arms are A's x and B's y; two coordinates.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Universal final : public JointKind {
 public:
  std::string_view name() const override { return "universal"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::w0}; }
  std::string initial_settings() const override {
    return "w0 (the rates about the cross's arms, [alpha rate, beta rate, 0] in B's joint axes; it starts with the "
           "frames aligned)";
  }
  std::vector<int> fixed_components(std::string_view key) const override {
    return key == joint_setting::w0.name ? std::vector<int>{3} : std::vector<int>{};
  }
  /// Starting aligned, the arms are the joint frames' x and y: w0's first two.
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.w_rel = setting_or_default(j, joint_setting::w0, B);
    return m;
  }
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
    const E w0 = m.setting_or_default(joint_setting::w0);
    Mobilizer::Rate& a = m.rate(m.sym.rate_junction("alpha"), "alpha", m.zero, B.at(w0, 1), false);
    a.W = m.ex;
    Mobilizer::Rate& b = m.rate(m.sym.rate_junction("beta"), "beta", m.zero, B.at(w0, 2), false);
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
