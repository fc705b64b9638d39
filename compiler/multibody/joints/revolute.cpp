// joints/revolute.cpp — a pin: rotation about the joint axis (A's z), one coordinate.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Revolute final : public JointKind {
 public:
  std::string_view name() const override { return "revolute"; }
  std::vector<const Setting*> settings() const override { return {&joint_setting::q0, &joint_setting::rate0, &joint_setting::torque, &joint_setting::motion}; }
  bool has_angle() const override { return true; }
  std::string initial_settings() const override { return "q0 (angle) and rate0"; }
  /// The points coincide and the axes stay aligned: 5 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    f.point(r);
    f.aligned(r);
  }
  void mobilize(Mobilizer& m) const override { turn_about_axis(m); }
};

}  // namespace

const JointKind& revolute_joint() {
  static const Revolute kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
