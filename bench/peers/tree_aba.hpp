// tree_aba.hpp — the 3-D models of tree_spec.hpp written by hand:
// Featherstone's articulated-body algorithm (Rigid Body Dynamics Algorithms,
// 2008, table 7.1) in spatial vectors [omega; v], body axes, O(N) per
// derivative, for trees of ball joints (3 dof) and universal joints (2 dof).
// The "practical limit" for these models: fixed-size Eigen types, the
// spatial transforms kept as a rotation E and an offset r (never a 6 x 6
// matrix), X^T I X done blockwise, the ball joint's motion subspace [1; 0]
// used by selecting columns, no heap in derivative().
//
// State: positions first (per body in order: a ball joint's quaternion
// [w, x, y, z] of the child's rotation relative to the parent, not
// renormalised in the state but normalised where it is read, as mbgc does; a
// universal joint's angles alpha, beta), then rates (ball: the relative
// angular velocity in the child's axes, with q' = 1/2 q (x) (0, w); universal:
// alpha', beta').
#pragma once
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "tree_spec.hpp"

namespace bench::tree {

class TreeAba {
 public:
  using V3 = Eigen::Vector3d;
  using M3 = Eigen::Matrix3d;
  using V6 = Eigen::Matrix<double, 6, 1>;
  using M6 = Eigen::Matrix<double, 6, 6>;

  explicit TreeAba(const TreeSpec& spec) : spec_(spec), n_(static_cast<int>(spec.bodies.size())), b_(n_) {
    nq_ = nv_ = 0;
    for (int i = 0; i < n_; ++i) {
      const BodySpec& s = spec.bodies[i];
      Body& b = b_[i];
      b.ball = s.joint == JointType::ball;
      b.parent = s.parent;
      b.r = s.at;
      b.u1 = s.axis1.normalized();
      b.u2 = s.axis2.normalized();
      b.iq = nq_, b.iv = nv_;
      nq_ += b.ball ? 4 : 2;
      nv_ += b.ball ? 3 : 2;
      // Spatial inertia about the frame origin: [Ic + m c~ c~^T, m c~; m c~^T, m 1].
      const M3 cx = skew(s.com);
      b.I.topLeftCorner<3, 3>() = M3(s.inertia.asDiagonal()) + s.mass * cx * cx.transpose();
      b.I.topRightCorner<3, 3>() = s.mass * cx;
      b.I.bottomLeftCorner<3, 3>() = s.mass * cx.transpose();
      b.I.bottomRightCorner<3, 3>() = s.mass * M3::Identity();
    }
    a0_ << 0, 0, 0, -spec.gravity;  // gravity: the ground accelerates up
  }

  int size() const { return nq_ + nv_; }

  /// The state at rest in the initial pose (ball joints at rot0, universal joints at 0).
  std::vector<double> initial_state() const {
    std::vector<double> y(size(), 0.0);
    for (int i = 0; i < n_; ++i) {
      if (!b_[i].ball) continue;
      const Eigen::Quaterniond& q = spec_.bodies[i].rot0;
      y[b_[i].iq] = q.w(), y[b_[i].iq + 1] = q.x(), y[b_[i].iq + 2] = q.y(), y[b_[i].iq + 3] = q.z();
    }
    return y;
  }

  /// The centres of mass in world axes, [x1, y1, z1, x2, ...], of state y.
  std::vector<double> com_positions(const double* y) {
    std::vector<double> out(3 * n_);
    std::vector<M3> R(n_);
    std::vector<V3> o(n_);
    for (int i = 0; i < n_; ++i) {
      const Body& b = b_[i];
      const M3 rel = relative_rotation(b, y + b.iq);
      if (b.parent < 0) {
        R[i] = rel, o[i] = b.r;
      } else {
        R[i] = R[b.parent] * rel, o[i] = o[b.parent] + R[b.parent] * b.r;
      }
      const V3 p = o[i] + R[i] * spec_.bodies[i].com;
      out[3 * i] = p.x(), out[3 * i + 1] = p.y(), out[3 * i + 2] = p.z();
    }
    return out;
  }

  void derivative(const double* y, double* ydot) {
    const double* q = y;
    const double* qd = y + nq_;
    double* dq = ydot;
    double* dv = ydot + nq_;
    // Outward: transforms, velocities, velocity-product accelerations, bias forces.
    for (int i = 0; i < n_; ++i) {
      Body& b = b_[i];
      const double* qi = q + b.iq;
      const double* wi = qd + b.iv;
      b.E = relative_rotation(b, qi).transpose();
      V3 wj;  // the joint's relative angular velocity, child axes (its linear part is 0)
      V3 cj = V3::Zero();
      if (b.ball) {
        wj = V3(wi[0], wi[1], wi[2]);
        dq[b.iq] = -0.5 * (qi[1] * wi[0] + qi[2] * wi[1] + qi[3] * wi[2]);
        dq[b.iq + 1] = 0.5 * (qi[0] * wi[0] + qi[2] * wi[2] - qi[3] * wi[1]);
        dq[b.iq + 2] = 0.5 * (qi[0] * wi[1] + qi[3] * wi[0] - qi[1] * wi[2]);
        dq[b.iq + 3] = 0.5 * (qi[0] * wi[2] + qi[1] * wi[1] - qi[2] * wi[0]);
      } else {
        // S = [s1 s2; 0 0]: s1 = R(u2, beta)^T u1 (the first shaft seen from the child), s2 = u2;
        // S' qdot = [-alpha' beta' u2 x s1; 0].
        const Eigen::AngleAxisd turn(-qi[1], b.u2);
        b.s1 = turn * b.u1;
        wj = b.s1 * wi[0] + b.u2 * wi[1];
        cj = -wi[0] * wi[1] * b.u2.cross(b.s1);
        dq[b.iq] = wi[0], dq[b.iq + 1] = wi[1];
      }
      V6 v;
      if (b.parent < 0) {
        v.setZero();
      } else {
        v = motion(b, b_[b.parent].v);
      }
      v.head<3>() += wj;
      b.v = v;
      // c = cJ + v x vJ, vJ = [wj; 0]
      b.c.head<3>() = v.head<3>().cross(wj) + cj;
      b.c.tail<3>() = v.tail<3>().cross(wj);
      // pA = v x* (I v)
      const V6 h = b.I * v;
      b.pA.head<3>() = v.head<3>().cross(h.head<3>()) + v.tail<3>().cross(h.tail<3>());
      b.pA.tail<3>() = v.head<3>().cross(h.tail<3>());
      b.IA = b.I;
    }
    // Inward: articulated inertias and bias forces.
    for (int i = n_ - 1; i >= 0; --i) {
      Body& b = b_[i];
      M6 Ia;
      V6 pa;
      if (b.ball) {
        b.U3 = b.IA.leftCols<3>();
        b.Dinv3 = b.U3.topRows<3>().inverse();
        b.u3 = -b.pA.head<3>();
        if (b.parent < 0) continue;
        Ia.noalias() = b.IA - b.U3 * b.Dinv3 * b.U3.transpose();
        pa.noalias() = b.pA + Ia * b.c + b.U3 * (b.Dinv3 * b.u3);
      } else {
        Eigen::Matrix<double, 3, 2> St;  // the angular rows of S
        St.col(0) = b.s1, St.col(1) = b.u2;
        b.U2.noalias() = b.IA.leftCols<3>() * St;
        b.Dinv2 = (St.transpose() * b.U2.topRows<3>()).inverse();
        b.u2v = -St.transpose() * b.pA.head<3>();
        if (b.parent < 0) continue;
        Ia.noalias() = b.IA - b.U2 * b.Dinv2 * b.U2.transpose();
        pa.noalias() = b.pA + Ia * b.c + b.U2 * (b.Dinv2 * b.u2v);
      }
      Body& p = b_[b.parent];
      add_inertia_to_parent(b, Ia, p.IA);
      add_force_to_parent(b, pa, p.pA);
    }
    // Outward: accelerations.
    for (int i = 0; i < n_; ++i) {
      Body& b = b_[i];
      V6 a = (b.parent < 0 ? motion(b, a0_) : motion(b, b_[b.parent].a)) + b.c;
      if (b.ball) {
        const V3 qdd = b.Dinv3 * (b.u3 - b.U3.transpose() * a);
        a.head<3>() += qdd;
        dv[b.iv] = qdd[0], dv[b.iv + 1] = qdd[1], dv[b.iv + 2] = qdd[2];
      } else {
        const Eigen::Vector2d qdd = b.Dinv2 * (b.u2v - b.U2.transpose() * a);
        a.head<3>() += b.s1 * qdd[0] + b.u2 * qdd[1];
        dv[b.iv] = qdd[0], dv[b.iv + 1] = qdd[1];
      }
      b.a = a;
    }
  }

 private:
  struct Body {
    bool ball = true;
    int parent = -1, iq = 0, iv = 0;
    V3 r, u1, u2, s1;
    M6 I;
    // per derivative
    M3 E;  // parent axes -> child axes
    V6 v, c, pA, a;
    M6 IA;
    Eigen::Matrix<double, 6, 3> U3;
    M3 Dinv3;
    V3 u3;
    Eigen::Matrix<double, 6, 2> U2;
    Eigen::Matrix2d Dinv2;
    Eigen::Vector2d u2v;
  };

  static M3 skew(const V3& v) {
    M3 m;
    m << 0, -v.z(), v.y(),  //
        v.z(), 0, -v.x(),   //
        -v.y(), v.x(), 0;
    return m;
  }

  /// The child's rotation relative to the parent (child axes -> parent axes).
  static M3 relative_rotation(const Body& b, const double* q) {
    if (b.ball) {
      const double w = q[0], x = q[1], y = q[2], z = q[3];
      const double s = 2 / (w * w + x * x + y * y + z * z);  // normalised: R(q / |q|)
      M3 R;
      R << 1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),  //
          s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x),   //
          s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y);
      return R;
    }
    return (Eigen::AngleAxisd(q[0], b.u1) * Eigen::AngleAxisd(q[1], b.u2)).toRotationMatrix();
  }

  /// X m for X = rot(E) xlt(r): [E w; E (v - r x w)].
  static V6 motion(const Body& b, const V6& m) {
    V6 out;
    out.head<3>() = b.E * m.head<3>();
    out.tail<3>() = b.E * (m.tail<3>() - b.r.cross(m.head<3>()));
    return out;
  }

  /// parent += X^T f: [E^T n + r x E^T f; E^T f].
  static void add_force_to_parent(const Body& b, const V6& f, V6& parent) {
    const V3 fp = b.E.transpose() * f.tail<3>();
    parent.head<3>() += b.E.transpose() * f.head<3>() + b.r.cross(fp);
    parent.tail<3>() += fp;
  }

  /// parent += X^T I X, blockwise: with I' = rot(E)^T I rot(E) = [A B; B^T C]
  /// and r~ = skew(r): [A + r~ B^T - B r~ - r~ C r~, B + r~ C; (.)^T, C].
  /// The diagonal blocks are symmetrised as they are added: rounding makes
  /// I = IA - U D^-1 U^T slightly unsymmetric, and along a chain of ball joints
  /// the unsymmetric part grows by about 4x per body (measured on the 32-rod
  /// spherical chain: 1e-16 at the leaf, O(1) at the root, without this), a
  /// mode the symmetric articulated inertia does not have.
  static void add_inertia_to_parent(const Body& b, const M6& I, M6& parent) {
    const M3 Et = b.E.transpose();
    const M3 A = Et * I.topLeftCorner<3, 3>() * b.E;
    const M3 B = Et * I.topRightCorner<3, 3>() * b.E;
    const M3 C = Et * I.bottomRightCorner<3, 3>() * b.E;
    const M3 rx = skew(b.r);
    const M3 rxC = rx * C;
    const M3 top_right = B + rxC;
    const M3 top_left = A + rx * B.transpose() - top_right * rx;
    parent.topLeftCorner<3, 3>() += 0.5 * (top_left + top_left.transpose());
    parent.topRightCorner<3, 3>() += top_right;
    parent.bottomLeftCorner<3, 3>() += top_right.transpose();
    parent.bottomRightCorner<3, 3>() += 0.5 * (C + C.transpose());
  }

  TreeSpec spec_;
  int n_, nq_ = 0, nv_ = 0;
  std::vector<Body> b_;
  V6 a0_;
};

}  // namespace bench::tree
