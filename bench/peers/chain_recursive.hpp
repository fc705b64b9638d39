// chain_recursive.hpp — the planar chain of examples/chain written by hand:
// Featherstone's articulated-body algorithm in planar spatial vectors
// [omega, vx, vy], O(N) per derivative. This is the "practical limit" the
// benchmark measures mbgc against: what an expert would write for this one
// model.
//
// Rod i: length l, mass m, inertia m l^2/12 about its centre, hanging along
// its body -y from its top joint; joint i turns rod i against rod i-1 about +z
// (rod 0 is the ground, joint 1 at the origin). Gravity g along world -y.
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace bench {

class ChainRecursive {
 public:
  ChainRecursive(int n, double length_m = 0.5, double mass_kg = 1.0, double g_m_per_s2 = 9.81)
      : n_(n), l_(length_m), g_(g_m_per_s2), X_(n), v_(n), c_(n), IA_(n), pA_(n), U_(n), d_(n), u_(n) {
    // Spatial inertia at the joint (the body frame's origin); centre at (0, -l/2).
    const double cx = 0, cy = -l_ / 2, ic = mass_kg * l_ * l_ / 12;
    I_ << ic + mass_kg * (cx * cx + cy * cy), -mass_kg * cy, mass_kg * cx,  //
        -mass_kg * cy, mass_kg, 0,                                          //
        mass_kg * cx, 0, mass_kg;
  }

  int size() const { return 2 * n_; }

  /// y = [q_1..q_n, qdot_1..qdot_n] -> ydot.
  void derivative(const double* y, double* ydot) {
    using V3 = Eigen::Vector3d;
    using M3 = Eigen::Matrix3d;
    const double* q = y;
    const double* qd = y + n_;
    // Outward: transforms, velocities, bias accelerations and forces.
    V3 v_parent = V3::Zero();
    for (int i = 0; i < n_; ++i) {
      const double s = std::sin(q[i]), c = std::cos(q[i]);
      const double ry = i == 0 ? 0.0 : -l_;  // joint i sits at the parent's bottom end
      // plnr(q, r) with r = (0, ry): parent motion vector -> this body's frame.
      X_[i] << 1, 0, 0,  //
          -c * ry, c, s,  //
          s * ry, -s, c;
      v_[i] = X_[i] * v_parent;
      v_[i](0) += qd[i];
      c_[i] = crm(v_[i]) * V3(qd[i], 0, 0);
      IA_[i] = I_;
      pA_[i] = crf(v_[i]) * (I_ * v_[i]);
      v_parent = v_[i];
    }
    // Inward: articulated inertias.
    for (int i = n_ - 1; i >= 0; --i) {
      U_[i] = IA_[i].col(0);
      d_[i] = U_[i](0);
      u_[i] = -pA_[i](0);
      if (i > 0) {
        const M3 Ia = IA_[i] - U_[i] * U_[i].transpose() / d_[i];
        const V3 pa = pA_[i] + Ia * c_[i] + U_[i] * (u_[i] / d_[i]);
        IA_[i - 1] += X_[i].transpose() * Ia * X_[i];
        pA_[i - 1] += X_[i].transpose() * pa;
      }
    }
    // Outward: accelerations. Gravity enters as the ground accelerating up.
    V3 a_parent(0, 0, g_);
    for (int i = 0; i < n_; ++i) {
      const V3 a = X_[i] * a_parent + c_[i];
      const double qdd = (u_[i] - U_[i].dot(a)) / d_[i];
      ydot[i] = qd[i];
      ydot[n_ + i] = qdd;
      a_parent = a;
      a_parent(0) += qdd;
    }
  }

 private:
  static Eigen::Matrix3d crm(const Eigen::Vector3d& v) {
    Eigen::Matrix3d m;
    m << 0, 0, 0,  //
        v(2), 0, -v(0),  //
        -v(1), v(0), 0;
    return m;
  }
  static Eigen::Matrix3d crf(const Eigen::Vector3d& v) { return -crm(v).transpose(); }

  int n_;
  double l_, g_;
  Eigen::Matrix3d I_;
  std::vector<Eigen::Matrix3d> X_;
  std::vector<Eigen::Vector3d> v_, c_;
  std::vector<Eigen::Matrix3d> IA_;
  std::vector<Eigen::Vector3d> pA_, U_;
  std::vector<double> d_, u_;
};

}  // namespace bench
