// joints/cylindrical.cpp — rotation about and sliding along the joint axis: two coordinates.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Cylindrical final : public JointKind {
 public:
  std::string_view name() const override { return "cylindrical"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::q0, &joint_setting::rate0, &joint_setting::torque, &joint_setting::motion, &joint_setting::d0, &joint_setting::ddot0}; }
  bool has_angle() const override { return true; }
  bool has_axial() const override { return true; }
  std::string initial_settings() const override { return "q0, rate0 (rotation) and d0, ddot0 (sliding)"; }
  /// B's point stays on A's axis and the axes stay aligned: 4 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    f.on_axis(r);
    f.aligned(r);
  }
  /// The angle on the drive (the drive's torque acts on it), the slide on its own junction.
  void mobilize(Mobilizer& m) const override {
    turn_about_axis(m);
    slide_along_axis(m, m.sym.slide(), joint_setting::d0, joint_setting::ddot0, false);
  }
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.axial = setting_or_default(j, joint_setting::d0, B), m.axial_rate = setting_or_default(j, joint_setting::ddot0, B);
    return m;
  }
};

}  // namespace

const JointKind& cylindrical_joint() {
  static const Cylindrical kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
