// joints/spherical.cpp — a ball joint: the points coincide, any relative rotation.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Spherical final : public JointKind {
 public:
  std::string_view name() const override { return "spherical"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::rot0, &joint_setting::w0}; }
  bool needs_orientation() const override { return false; }
  std::string initial_settings() const override {
    return "rot0 (relative rotation) and w0 (relative angular velocity, B's joint axes)";
  }
  void rows(const JointFrames& f, std::vector<E>& r) const override { f.point(r); }
  void mobilize(Mobilizer& m) const override { m.ball(); }
  /// The relative rotation rot0 and angular velocity w0 (default: none).
  InitialMotion initial(const Build& B, const Joint& j) const override {
    InitialMotion m = JointKind::initial(B, j);
    m.qrel = setting_or_default(j, joint_setting::rot0, B);
    m.w_rel = setting_or_default(j, joint_setting::w0, B);
    return m;
  }
};

}  // namespace

const JointKind& spherical_joint() {
  static const Spherical kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
