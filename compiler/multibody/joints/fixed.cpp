// joints/fixed.cpp — a weld: no relative motion.
#include "multibody/joint_kind.hpp"

namespace mbgc::multibody::detail {
namespace {

class Fixed final : public JointKind {
 public:
  std::string_view name() const override { return "fixed"; }
  /// Points coincide, axes aligned, not turned: 6 rows.
  void rows(const JointFrames& f, std::vector<E>& r) const override {
    f.point(r);
    f.aligned(r);
    r.push_back(f.perp(f.A.X, f.Bf.Y));
  }
  /// No coordinates: the child moves with its parent.
  void mobilize(Mobilizer&) const override {}
};

}  // namespace

const JointKind& fixed_joint() {
  static const Fixed kind;
  return kind;
}

}  // namespace mbgc::multibody::detail
