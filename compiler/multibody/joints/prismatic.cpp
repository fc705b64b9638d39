// joints/prismatic.cpp — a slider: translation along the joint axis, one coordinate.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Prismatic final : public JointKind {
 public:
  std::string_view name() const override { return "prismatic"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::q0, &joint_setting::rate0, &joint_setting::force, &joint_setting::motion}; }
  bool has_axial() const override { return true; }
  std::string initial_settings() const override { return "q0 (displacement) and rate0"; }
  /// B's point on A's axis, the axes aligned and not turned about it: 5 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    f.on_axis(r);
    f.aligned(r);
    r.push_back(f.perp(f.A.X, f.Bf.Y));
  }
  void mobilize(Mobilizer& m) const override {
    slide_along_axis(m, m.sym.drive(), joint_setting::q0, joint_setting::rate0, m.prescribed());
  }
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.axial = setting_or_default(j, joint_setting::q0, B), m.axial_rate = setting_or_default(j, joint_setting::rate0, B);
    return m;
  }
};

}  // namespace

const JointKind& prismatic_joint() {
  static const Prismatic kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
