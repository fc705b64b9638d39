// fe/craig_bampton.hpp — the Craig–Bampton reduction of an FE model
// (reference: flexible-mbs-vehicle-dynamics, §2.5, eqs. 2.218–2.225).
//
//   1. Each interface ties its nodes rigidly to a point with 6 DOFs (for a
//      single node of a beam mesh, its own DOFs). The frame interface is held:
//      the body's frame is attached to it (a "tangent" frame), which removes
//      the rigid-body motion.
//   2. Static constraint modes (eq. 2.219): for each DOF of each other
//      interface, the static shape of a unit displacement there with the
//      other boundary DOFs held, q_i = -K_ii^-1 K_ib.
//   3. Fixed-interface normal modes (eq. 2.222): the lowest `normal_modes`
//      of K_ii v = lambda M_ii v (Spectra, Lanczos on L^-1 M_ii L^-T with
//      K_ii = L L^T, so a mass matrix with massless DOFs is fine).
//   4. The basis [constraint modes, normal modes] is made M- and
//      K-orthogonal by the eigenvectors of the reduced pair (eqs. 2.224–2.225)
//      and the lowest `keep` of them are kept, each scaled so that its largest
//      nodal translation is +1 (its coordinate eta is then a length, m).
// Sparse matrices throughout; the dense matrices are n_DOF x (modes).
#pragma once

#include <optional>
#include <vector>

#include "matrix_market.hpp"
#include "mesh.hpp"

namespace mbgc::fe {

struct ReductionRequest {
  std::vector<Attachment> interfaces;  // interfaces[frame] carries the body frame
  int frame = 0;
  int normal_modes = 0;                // fixed-interface modes (eq. 2.222)
  int keep = -1;                       // modes kept after eq. 2.225; -1: all
};

struct Reduction {
  Eigen::MatrixXd modes;         // DOFs x n: each mode's FE DOF vector (eq. 2.225)
  Eigen::VectorXd omega;         // rad/s, each mode's frequency in the reduced model, ascending
  Eigen::VectorXd fixed_interface_omega;  // rad/s, of the normal modes of step 3
  int constraint_modes = 0;
};

std::optional<Reduction> craig_bampton(const Mesh& mesh, const SparseMatrix& stiffness, const SparseMatrix& mass,
                                       const ReductionRequest& request, ir::Diagnostics& diags);

/// The translation and small rotation at `a.at` per unit of each mode
/// (3 x n each): an interface's or a single beam node's own DOFs, otherwise
/// the rigid motion that fits its nodes' translations best (least squares).
struct PointMotion {
  Eigen::MatrixXd shape, slope;
};
PointMotion point_motion(const Mesh& mesh, const Attachment& a, const Eigen::MatrixXd& modes);

}  // namespace mbgc::fe
