// DART: the chain as a Skeleton of RevoluteJoints about z (each at the
// parent's bottom end, the child's frame at its top end), inertias about the
// centres of mass, the same RK4 loop as the hand-written model around
// Skeleton::computeForwardDynamics() (DART's O(N) articulated-body
// algorithm). A revolute joint's position is its angle and its velocity the
// angle's rate, so plain RK4 on DART's [q; dq] is the same integration as the
// other engines'.
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Inertia.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/config.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "engine.hpp"
#include "rk4.hpp"

namespace bench {

Engine dart_engine(int n) {
  using namespace dart::dynamics;
  SkeletonPtr skel = Skeleton::create("chain");
  skel->setGravity(Eigen::Vector3d(0, -kGravity_m_per_s2, 0));
  const double i_bend = kMass_kg * kLength_m * kLength_m / 12, i_spin = kMass_kg * kRadius_m * kRadius_m / 2;
  BodyNode* parent = nullptr;
  for (int i = 1; i <= n; ++i) {
    RevoluteJoint::Properties joint;
    joint.mName = "j" + std::to_string(i);
    joint.mT_ParentBodyToJoint.translation() = Eigen::Vector3d(0, i == 1 ? 0.0 : -kLength_m, 0);
    joint.mAxis = Eigen::Vector3d::UnitZ();
    BodyNode* body = skel->createJointAndBodyNodePair<RevoluteJoint>(
                             parent, joint, BodyNode::AspectProperties("rod" + std::to_string(i))).second;
    body->setInertia(Inertia(kMass_kg, Eigen::Vector3d(0, -kLength_m / 2, 0),
                             Eigen::Vector3d(i_bend, i_spin, i_bend).asDiagonal().toDenseMatrix()));
    parent = body;
  }
  struct Work {
    SkeletonPtr skel;
    Eigen::VectorXd q, qd;
  };
  auto w = std::make_shared<Work>(Work{skel, Eigen::VectorXd(n), Eigen::VectorXd(n)});
  return {"DART " DART_VERSION, [w, n](double h, long steps) {
            std::vector<double> y(2 * n, 0.0);
            for (int i = 0; i < n; ++i) y[i] = kStartAngle_rad;
            rk4(
                [&](double, const double* x, double* xdot) {
                  // A state blown up at a step too large: Debian's DART is built with assertions and aborts
                  // the process when its bias forces overflow into NaN (no state here comes near 1e50).
                  bool ok = true;
                  for (int i = 0; i < 2 * n; ++i) ok &= std::abs(x[i]) < 1e50;
                  if (!ok) {
                    std::fill(xdot, xdot + 2 * n, std::numeric_limits<double>::quiet_NaN());
                    return;
                  }
                  for (int i = 0; i < n; ++i) w->q[i] = x[i], w->qd[i] = x[n + i];
                  w->skel->setPositions(w->q);
                  w->skel->setVelocities(w->qd);
                  w->skel->computeForwardDynamics();
                  for (int i = 0; i < n; ++i) xdot[i] = x[n + i], xdot[n + i] = w->skel->getAcceleration(i);
                },
                y, h, steps);
            return std::vector<double>(y.begin(), y.begin() + n);
          }};
}

}  // namespace bench
