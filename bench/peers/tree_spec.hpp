// tree_spec.hpp — the two 3-D models of the peer benchmark as data, so that
// the hand-written model, MuJoCo, Simbody and DART are built from one
// description (mbgc reads the same models from binary_tree.mbg and
// spherical_chain.mbg; tree_peers checks that every engine starts from the
// same pose and that mbgc and the hand-written model agree).
//
// Conventions (those of mbgc's multibody layer, docs/multibody.md):
// every body's frame origin is its joint point on the child side (the rods'
// `top` / `base` point, [0, 0, 0]); `at` is the joint point on the parent, in
// the parent's body axes (world axes for the ground). A ball joint's
// coordinate is the child's rotation relative to the parent (body axes), a
// unit quaternion, started at `rot0`; its rates are the relative angular
// velocity in the child's axes. A universal joint turns the child by
// R(axis1, alpha) R(axis2, beta) relative to the parent (axis1 and axis2 in
// the body axes, axis2 turned by the first rotation), started at 0, 0.
// mbgc's `universal(..) { axis = [0, 1, 0] }` puts its joint frame's z on the
// axis (x, y by the shortest rotation taking +z there: x = [1, 0, 0],
// y = [0, 0, -1]) and turns about the frame's x, then the turned y: here
// axis1 = [1, 0, 0], axis2 = [0, 0, -1].
#pragma once
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace bench::tree {

enum class JointType { ball, universal };

struct BodySpec {
  int parent = -1;  // index of the parent body; -1: the ground
  JointType joint = JointType::ball;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();                 // joint point on the parent (parent body axes)
  Eigen::Quaterniond rot0 = Eigen::Quaterniond::Identity();     // ball: initial relative rotation
  Eigen::Vector3d axis1 = Eigen::Vector3d::UnitX(), axis2 = Eigen::Vector3d::UnitY();  // universal
  double mass = 1;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // body axes, from the joint point (frame origin)
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();  // principal moments about the centre of mass, body axes
};

struct TreeSpec {
  std::string name;
  Eigen::Vector3d gravity;
  std::vector<BodySpec> bodies;  // a parent comes before its children
};

inline Eigen::Quaterniond quat_axis_angle(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

/// bench/peers/binary_tree.mbg (tests/numeric/models/binary_tree.mbg with an
/// output per centre-of-mass coordinate): rod k (1-based) hangs from rod k/2,
/// on a ball joint at its `left` point when k is even, on a universal joint
/// at its `right` point when k is odd; rod 1 on a ball joint at the origin.
inline TreeSpec binary_tree_spec(int n) {
  const double l = 0.4, m = 0.5;
  TreeSpec t{"binary tree", Eigen::Vector3d(0, -9.81, 0), {}};
  for (int k = 1; k <= n; ++k) {
    BodySpec b;
    b.mass = m;
    b.com = Eigen::Vector3d(0, -l / 2, 0);
    b.inertia = Eigen::Vector3d(m * l * l / 12, 0.0005, m * l * l / 12);
    if (k == 1) {
      b.parent = -1;
      b.rot0 = quat_axis_angle(Eigen::Vector3d::UnitX(), 0.2);
    } else if (k % 2 == 0) {
      b.parent = k / 2 - 1;
      b.at = Eigen::Vector3d(-0.05, -l, 0.02);  // rod{k/2}.left
      b.rot0 = quat_axis_angle(Eigen::Vector3d::UnitZ(), 0.3);
    } else {
      b.parent = k / 2 - 1;
      b.joint = JointType::universal;
      b.at = Eigen::Vector3d(0.05, -l, -0.02);  // rod{k/2}.right
      b.axis1 = Eigen::Vector3d(1, 0, 0);       // axis = [0, 1, 0]: the joint frame's x ...
      b.axis2 = Eigen::Vector3d(0, 0, -1);      // ... and y, in body axes
    }
    t.bodies.push_back(b);
  }
  return t;
}

/// bench/peers/spherical_chain.mbg: n rods (0.5 m, 1 kg, radius 0.01 m, along
/// body x) on ball joints, rod 1 at the origin, each joint turned by 0.1 rad
/// about [0, 0.6, 0.8] at the start (a helix, bent in 3-D), gravity along -z.
inline TreeSpec spherical_chain_spec(int n) {
  const double l = 0.5, m = 1, r = 0.01;
  TreeSpec t{"spherical chain", Eigen::Vector3d(0, 0, -9.81), {}};
  for (int k = 1; k <= n; ++k) {
    BodySpec b;
    b.parent = k - 2;
    b.at = k == 1 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(l, 0, 0);  // ground.pivot, rod{k-1}.tip
    b.rot0 = quat_axis_angle(Eigen::Vector3d(0, 0.6, 0.8), 0.1);
    b.mass = m;
    b.com = Eigen::Vector3d(l / 2, 0, 0);
    b.inertia = Eigen::Vector3d(m * r * r / 2, m * l * l / 12, m * l * l / 12);
    t.bodies.push_back(b);
  }
  return t;
}

}  // namespace bench::tree
