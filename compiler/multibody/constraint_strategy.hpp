// multibody/constraint_strategy.hpp — how a joint's constraint is held, a
// type per strategy, as joint kinds are (joint_kind.hpp): multipliers
// (`lagrange`), a penalty spring and damper (`penalty`), or joint
// coordinates (`coordinates`), where a joint of the spanning tree is a
// coordinate of its child body (joint_coordinates.cpp) and a joint that
// closes a loop holds its rows with Baumgarte-stabilised multipliers.
//
// The spanning-tree pass chooses each joint's strategy (an `auto` joint's:
// Strategy, expand.hpp); the writer asks the joint's strategy, never which
// one it is.
#pragma once

#include <functional>

#include "ir/expanded.hpp"
#include "multibody/build.hpp"
#include "multibody/expand.hpp"
#include "multibody/joint_symbols.hpp"
#include "multibody/model.hpp"

namespace mbgc::multibody::detail {

/// What a strategy reads to hold a joint's rows, and where it writes the
/// parameters its law reads.
struct HoldContext {
  const Build& B;
  const Joint& joint;
  const JointSym& jn;
  const Frame& a;
  const Frame& b;
  std::function<void(const Sym&, E)> param;  // a run-time parameter of the joint
};

class ConstraintStrategy {
 public:
  virtual ~ConstraintStrategy() = default;
  /// Whether a joint of the spanning tree places its child by a joint coordinate.
  virtual bool tree_coordinates() const { return false; }
  /// What a joint's rows are for, and what to do about a free joint, which has none.
  virtual const char* rows_are_for() const = 0;
  virtual const char* free_joint_hint() const = 0;
  /// The CN law beyond its rows `g`: what holds them, the parameters it reads written by `c.param`.
  virtual void hold(const HoldContext& c, ir::ConstraintLaw& law) const = 0;
};

/// The strategy `s` names (not Auto: the spanning-tree pass resolves that).
const ConstraintStrategy& constraint_strategy(Strategy s);

}  // namespace mbgc::multibody::detail
