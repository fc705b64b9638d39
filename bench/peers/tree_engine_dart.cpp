// DART: a 3-D model of tree_spec.hpp as a Skeleton of BallJoints and
// UniversalJoints (each at the joint point on the parent, the child's frame
// at its own joint point; DART's UniversalJoint turns the child by
// R(axis1, q1) R(axis2, q2), as tree_spec.hpp says), inertias about the
// centres of mass, accelerations from Skeleton::computeForwardDynamics()
// (DART's O(N) articulated-body algorithm).
//
// Integration: DART's ball-joint position is a rotation vector (its
// exponential coordinates) and its velocity the relative angular velocity in
// the child's joint frame (here the child's body axes), so the position's
// derivative is not the velocity and plain RK4 on DART's [q; dq] would be
// wrong. We convert instead: the state is that of the hand-written model (a
// ball joint's unit quaternion, its relative rotation, with
// q' = 1/2 q (x) (0, w); a universal joint's two angles, which are DART's own
// coordinates), integrated by the same rk4.hpp. Each derivative sets DART's
// positions to the rotation vectors of the quaternions
// (BallJoint::convertToPositions, the log map) and its velocities to the
// angular velocities; DART's accelerations of a ball joint are dw/dt in the
// child's axes (its Jacobian is constant there), which is what the state's
// rates need.
#include <dart/config.hpp>
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Inertia.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/UniversalJoint.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <tuple>

#include "tree_engines.hpp"

namespace bench::tree {
namespace {

/// False if any of x[0..n) is NaN, infinite or beyond 1e50 (a state blown up
/// at a step too large: Debian's DART is built with assertions, and aborts the
/// process when its bias forces overflow into NaN; no state of these models
/// comes near 1e50).
bool finite(const double* x, int n) {
  bool ok = true;
  for (int i = 0; i < n; ++i) ok &= std::abs(x[i]) < 1e50;
  return ok;
}

}  // namespace

Engine dart_engine(const TreeSpec& spec) {
  using namespace dart::dynamics;
  struct Work {
    SkeletonPtr skel;
    std::vector<BodyNode*> nodes;
    std::vector<bool> ball;
    std::vector<int> iq, iv, dof;  // per body: state offsets of its positions and rates, DART's first dof index
    int nq = 0, nv = 0;
    std::vector<double> y0;
    Eigen::VectorXd q, dq;
  };
  auto w = std::make_shared<Work>();
  w->skel = Skeleton::create(spec.name);
  w->skel->setGravity(spec.gravity);
  for (const BodySpec& b : spec.bodies) {
    BodyNode* parent = b.parent < 0 ? nullptr : w->nodes[b.parent];
    Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
    at.translation() = b.at;
    const std::string id = std::to_string(w->nodes.size() + 1);
    Joint* joint = nullptr;
    BodyNode* node = nullptr;
    if (b.joint == JointType::ball) {
      BallJoint::Properties p;
      p.mName = "j" + id;
      p.mT_ParentBodyToJoint = at;
      std::tie(joint, node) =
          w->skel->createJointAndBodyNodePair<BallJoint>(parent, p, BodyNode::AspectProperties("rod" + id));
    } else {
      UniversalJoint::Properties p;
      p.mName = "j" + id;
      p.mT_ParentBodyToJoint = at;
      p.mAxis = {b.axis1, b.axis2};
      std::tie(joint, node) =
          w->skel->createJointAndBodyNodePair<UniversalJoint>(parent, p, BodyNode::AspectProperties("rod" + id));
    }
    node->setInertia(Inertia(b.mass, b.com, b.inertia.asDiagonal().toDenseMatrix()));
    w->nodes.push_back(node);
    const bool ball = b.joint == JointType::ball;
    w->ball.push_back(ball);
    w->iq.push_back(w->nq);
    w->iv.push_back(w->nv);
    w->dof.push_back(static_cast<int>(joint->getIndexInSkeleton(0)));
    w->nq += ball ? 4 : 2;
    w->nv += ball ? 3 : 2;
  }
  w->y0.assign(w->nq + w->nv, 0.0);
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
    if (!w->ball[i]) continue;
    const Eigen::Quaterniond& r = spec.bodies[i].rot0;
    double* q = &w->y0[w->iq[i]];
    q[0] = r.w(), q[1] = r.x(), q[2] = r.y(), q[3] = r.z();
  }
  w->q.setZero(w->skel->getNumDofs());
  w->dq.setZero(w->skel->getNumDofs());
  // y (the state above) -> DART's positions and velocities.
  auto set_state = [](Work& w, const double* x) {
    const double* v = x + w.nq;
    for (std::size_t i = 0; i < w.nodes.size(); ++i) {
      const double* qi = x + w.iq[i];
      const double* vi = v + w.iv[i];
      const int d = w.dof[i];
      if (w.ball[i]) {
        const Eigen::Quaterniond quat(qi[0], qi[1], qi[2], qi[3]);
        w.q.segment<3>(d) = BallJoint::convertToPositions(quat.normalized().toRotationMatrix());
        w.dq.segment<3>(d) = Eigen::Vector3d(vi[0], vi[1], vi[2]);
      } else {
        w.q[d] = qi[0], w.q[d + 1] = qi[1];
        w.dq[d] = vi[0], w.dq[d + 1] = vi[1];
      }
    }
    w.skel->setPositions(w.q);
    w.skel->setVelocities(w.dq);
  };
  return {"DART " DART_VERSION, [w, set_state](double h, long steps) {
            std::vector<double> y = w->y0;
            rk4(
                [&](double, const double* x, double* xdot) {
                  if (!finite(x, w->nq + w->nv)) {
                    std::fill(xdot, xdot + w->nq + w->nv, std::numeric_limits<double>::quiet_NaN());
                    return;
                  }
                  set_state(*w, x);
                  w->skel->computeForwardDynamics();
                  const double* v = x + w->nq;
                  double* dv = xdot + w->nq;
                  for (std::size_t i = 0; i < w->nodes.size(); ++i) {
                    const double* qi = x + w->iq[i];
                    const double* vi = v + w->iv[i];
                    double* dqi = xdot + w->iq[i];
                    const int d = w->dof[i];
                    if (w->ball[i]) {
                      dqi[0] = -0.5 * (qi[1] * vi[0] + qi[2] * vi[1] + qi[3] * vi[2]);
                      dqi[1] = 0.5 * (qi[0] * vi[0] + qi[2] * vi[2] - qi[3] * vi[1]);
                      dqi[2] = 0.5 * (qi[0] * vi[1] + qi[3] * vi[0] - qi[1] * vi[2]);
                      dqi[3] = 0.5 * (qi[0] * vi[2] + qi[1] * vi[1] - qi[2] * vi[0]);
                      for (int k = 0; k < 3; ++k) dv[w->iv[i] + k] = w->skel->getAcceleration(d + k);
                    } else {
                      dqi[0] = vi[0], dqi[1] = vi[1];
                      for (int k = 0; k < 2; ++k) dv[w->iv[i] + k] = w->skel->getAcceleration(d + k);
                    }
                  }
                },
                y, h, steps);
            std::vector<double> out;
            if (!finite(y.data(), w->nq + w->nv)) return std::vector<double>(3 * w->nodes.size(), NAN);
            set_state(*w, y.data());
            for (BodyNode* node : w->nodes) {
              const Eigen::Vector3d p = node->getCOM();
              out.insert(out.end(), {p.x(), p.y(), p.z()});
            }
            return out;
          }};
}

}  // namespace bench::tree
