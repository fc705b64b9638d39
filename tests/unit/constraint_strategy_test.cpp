// The constraint strategies, a type each: what each writes to hold a joint's rows.
#include <gtest/gtest.h>

#include "multibody/constraint_strategy.hpp"

namespace {

namespace ir = mbgc::ir;
using namespace mbgc::multibody;
using namespace mbgc::multibody::detail;

/// The settings strategy `s` adds to a CN's law, and the parameters it writes, for a joint between two bodies.
std::pair<std::vector<std::string>, std::vector<std::string>> held_by(Strategy s) {
  ir::AstJoint decl;
  decl.name = "j";
  Joint joint;
  joint.decl = &decl;
  SymbolIds ids;
  const Build B({}, ids);
  Frame a, b;
  a.body = "link1", b.body = "link2";
  std::vector<std::string> params, settings;
  ir::ConstraintLaw law;
  const JointSym jn("j");
  constraint_strategy(s).hold({B, joint, jn, a, b, [&](const Sym& name, E) { params.push_back(name.str()); }}, law);
  for (const auto& f : ir::ConstraintLaw::fields())
    if (law.*f.member) settings.emplace_back(f.key);
  return {settings, params};
}

TEST(ConstraintStrategy, EachHoldsTheRowsItsOwnWay) {
  using V = std::vector<std::string>;
  EXPECT_EQ(held_by(Strategy::Lagrange), std::make_pair(V{}, V{}));  // multipliers: g = 0 alone
  EXPECT_EQ(held_by(Strategy::Penalty), std::make_pair(V{"stiffness", "damping"}, V{"j.stiffness", "j.damping"}));
  EXPECT_EQ(held_by(Strategy::Coordinates), std::make_pair(V{"stabilisation"}, V{"j.stabilisation"}));  // a cut joint
  EXPECT_TRUE(constraint_strategy(Strategy::Coordinates).tree_coordinates());
  EXPECT_FALSE(constraint_strategy(Strategy::Penalty).tree_coordinates());
}

TEST(ConstraintStrategy, AnAutoLeftUnresolvedIsTheCompilersMistake) {
  EXPECT_THROW(constraint_strategy(Strategy::Auto), ir::InternalError);
}

}  // namespace
