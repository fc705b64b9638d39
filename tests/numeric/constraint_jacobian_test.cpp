// The layout and the constraint Jacobian mbgc states (unknown_role,
// constraint_jacobian) against what the generated constraints() does: G =
// dg/dx must be its derivative (central differences), its pattern must hold
// every state g reads, and those states must be positions. Five models:
// lagrange (a DAE), penalty (an ODE), modal coordinates (a flexible rocker),
// Andrews' squeezer (seven bodies, a DAE), and a cut joint in joint
// coordinates, whose g reads the tree's pose signals (the chain rule through
// the assignments).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "constraint_crank_rocker_penalty.hpp"
#include "constraint_cut_joint.hpp"
#include "sparsity_andrews.hpp"
#include "sparsity_crank_rocker.hpp"
#include "sparsity_crank_rocker_flexible.hpp"

namespace {

using mbgrt::UnknownRole;

void expect_g_is_differentiated(mbgrt::Model& m, std::size_t expected_multipliers) {
  const std::size_t n = m.size(), ns = m.state_count(), np = m.position_constraint_count();
  ASSERT_GT(np, 0u);
  std::vector<double> y(n), yp(n);
  m.initial(0.0, y.data(), yp.data());
  // a generic point: off the constraint manifold, no angle at a special value
  for (std::size_t i = 0; i < ns; ++i) y[i] += 0.013 * std::sin(1.0 + static_cast<double>(i));

  std::size_t multipliers = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const UnknownRole r = m.unknown_role(i);
    if (i < ns)
      EXPECT_TRUE(r == UnknownRole::position || r == UnknownRole::velocity) << m.variable_name(i);
    else
      EXPECT_TRUE(r == UnknownRole::multiplier || r == UnknownRole::stabiliser || r == UnknownRole::algebraic)
          << m.variable_name(i);
    multipliers += r == UnknownRole::multiplier;
  }
  EXPECT_EQ(multipliers, expected_multipliers);

  std::vector<long> starts, columns;
  m.constraint_jacobian_pattern(starts, columns);
  ASSERT_EQ(starts.size(), np + 1);
  ASSERT_EQ(static_cast<std::size_t>(starts.back()), columns.size());
  std::vector<double> values(columns.size());
  const double t = 0.1;
  m.constraint_jacobian(t, y.data(), values.data());

  std::vector<double> cp(np + m.velocity_constraint_count()), cm(cp.size());
  std::size_t compared = 0;
  for (std::size_t j = 0; j < ns; ++j) {
    const double saved = y[j], h = 1e-6 * (1.0 + std::abs(saved));
    y[j] = saved + h;
    m.constraints(t, y.data(), cp.data());
    y[j] = saved - h;
    m.constraints(t, y.data(), cm.data());
    y[j] = saved;
    for (std::size_t r = 0; r < np; ++r) {
      const double fd = (cp[r] - cm[r]) / (2.0 * h);
      long at = -1;
      for (long e = starts[r]; e < starts[r + 1]; ++e)
        if (columns[static_cast<std::size_t>(e)] == static_cast<long>(j)) at = e;
      const std::string where = m.constraint_name(r) + " by " + m.variable_name(j);
      if (at < 0) {
        EXPECT_EQ(fd, 0.0) << where << ": g reads a state its pattern leaves out";
        continue;
      }
      EXPECT_EQ(m.unknown_role(j), UnknownRole::position) << where;
      EXPECT_NEAR(values[static_cast<std::size_t>(at)], fd, 1e-6 * (1.0 + std::abs(fd))) << where;
      ++compared;
    }
  }
  EXPECT_EQ(compared, columns.size());
}

TEST(ConstraintJacobian, IsTheDerivativeOfGForTheCrankRocker) {
  crank_rocker::crank_rocker_model m;
  expect_g_is_differentiated(m, m.position_constraint_count());
}

TEST(ConstraintJacobian, IsTheDerivativeOfGInPenaltyForm) {
  crank_rocker_penalty::crank_rocker_model m;
  expect_g_is_differentiated(m, 0);
}

TEST(ConstraintJacobian, IsTheDerivativeOfGThroughModalCoordinates) {
  crank_rocker_flexible::crank_rocker_flexible_model m;
  expect_g_is_differentiated(m, m.position_constraint_count());
}

TEST(ConstraintJacobian, IsTheDerivativeOfGForAndrewsSqueezer) {
  andrews::andrews_model m;
  expect_g_is_differentiated(m, m.position_constraint_count());
}

TEST(ConstraintJacobian, IsTheDerivativeOfACutJointsGThroughThePoseSignals) {
  cut_joint::cut_joint_model m;
  expect_g_is_differentiated(m, 0);
}

}  // namespace
