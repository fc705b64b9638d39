// fe/invariants.hpp — the inertia invariants of a reduced body (the records
// of docs/modal_format.md) from the FE model's mass matrix and modes.
//
// Exact for any element, from rigid-body DOF vectors (T_i: a unit
// translation along axis i; R_i: a unit rotation about axis i through the
// frame origin) and the modes, because an FE space holds rigid motions:
//   mass m = T_i^T M T_i, first moment s_k = T_i^T M R_j (eps_ijk = 1),
//   inertia J_ij = R_i^T M R_j, mean C_ik = T_i^T M Phi_k,
//   the rotation-mode coupling ax(A_k)_i = R_i^T M Phi_k,
//   the modal mass tr(B_kl) = Phi_k^T M Phi_l.
// So the body's mass matrix at eta = 0 is the FE mass matrix projected on
// rigid motion and modes, exactly.
//
// The rest of A_k and B_kl (how the inertia changes with deformation) needs
// the mass of each direction separately, int u_i w_j dm. A mesh with
// translational DOFs only whose mass matrix is M = M_s (x) I_3 (isoparametric
// solids: one shape function for x, y and z) gives it exactly from M_s. For
// other meshes (beams, shells) it comes from lumped nodal masses (M T_i at
// each node), which converge to the consistent values as the mesh is refined;
// `exact_directions` says which one was used.
#pragma once

#include <string>
#include <vector>

#include "matrix_market.hpp"
#include "mesh.hpp"

namespace mbgc::fe {

struct Invariants {
  double mass = 0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::MatrixXd mean;                 // 3 x n
  std::vector<Eigen::Matrix3d> moment;  // A_k
  std::vector<Eigen::Matrix3d> product; // B_kl at k * n + l (both triangles)
  Eigen::MatrixXd stiffness;            // n x n
  bool exact_directions = false;
  Eigen::Vector3d mass_by_axis = Eigen::Vector3d::Zero();  // T_i^T M T_i: equal for a structural mass matrix
};

/// `origin` is the body frame's origin in the FE axes.
Invariants inertia_invariants(const Mesh& mesh, const SparseMatrix& mass, const SparseMatrix& stiffness,
                              const Eigen::MatrixXd& modes, const Eigen::Vector3d& origin);

}  // namespace mbgc::fe
