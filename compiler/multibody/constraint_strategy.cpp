// multibody/constraint_strategy.cpp — the three ways a joint's rows are held.
#include "multibody/constraint_strategy.hpp"

#include "multibody/symbols.hpp"

namespace mbgc::multibody::detail {
namespace {

constexpr const char* kMultipliersHint =
    "give it joint coordinates (constraints = coordinates), or remove it: with multipliers a floating body needs no "
    "joint (body settings r0, v0, q0, w0)";

/// Multipliers: the CN's effort is whatever holds g = 0 (an index-3 DAE, reduced by differentiation).
class Multipliers : public ConstraintStrategy {
 public:
  const char* rows_are_for() const override { return "multipliers"; }
  const char* free_joint_hint() const override { return kMultipliersHint; }
  void hold(const HoldContext&, ir::ConstraintLaw&) const override {}
};

/// A penalty: e = stiffness g + damping g', an ODE instead of a multiplier.
class Penalty : public ConstraintStrategy {
 public:
  const char* rows_are_for() const override { return "multipliers"; }
  const char* free_joint_hint() const override { return kMultipliersHint; }
  void hold(const HoldContext& c, ir::ConstraintLaw& law) const override {
    const Build& B = c.B;
    // Stiffness and damping from the lighter body: natural frequency 1000 rad/s, critically damped.
    std::vector<E> masses;
    for (const Frame* f : {&c.a, &c.b})
      if (!f->kind.ground()) masses.push_back(B.ref(BodySym(f->body).mass()));
    E m = masses.size() == 1 ? masses[0] : B.call("min", {masses[0], masses[1]});
    c.param(c.jn.stiffness(), setting_or(c.joint, joint_setting::stiffness, B.op('*', m, B.num(1e6))));
    c.param(c.jn.damping(), setting_or(c.joint, joint_setting::damping,
                                       B.op('*', B.num(2), B.call("sqrt", {B.op('*', m, B.ref(c.jn.stiffness()))}))));
    law.stiffness = B.ref(c.jn.stiffness());
    law.damping = B.ref(c.jn.damping());
  }
};

/// Joint coordinates: a tree joint is its child's coordinate; a cut joint's
/// rows' multipliers keep g'' + 2 w g' + w^2 g = 0 (Baumgarte, critically
/// damped at w rad/s), an acceleration-level condition solved with the
/// tree's accelerations.
class Coordinates : public ConstraintStrategy {
 public:
  bool tree_coordinates() const override { return true; }
  const char* rows_are_for() const override { return "closing a loop"; }
  const char* free_joint_hint() const override {
    return "a free joint belongs on a tree from ground: attach its body to nothing else that reaches ground";
  }
  void hold(const HoldContext& c, ir::ConstraintLaw& law) const override {
    c.param(c.jn.stabilisation(), setting_or_default(c.joint, joint_setting::stabilisation, c.B));
    law.stabilisation = c.B.ref(c.jn.stabilisation());
  }
};

}  // namespace

const ConstraintStrategy& constraint_strategy(Strategy s) {
  static const Multipliers multipliers;
  static const Penalty penalty;
  static const Coordinates coordinates;
  switch (s) {
    case Strategy::Penalty: return penalty;
    case Strategy::Coordinates: return coordinates;
    case Strategy::Lagrange: return multipliers;
    case Strategy::Auto: break;
  }
  throw ir::InternalError("a joint's strategy is still `auto` where its constraint is written (the spanning-tree pass resolves it)");
}

}  // namespace mbgc::multibody::detail
