// fe/craig_bampton.cpp
#include "craig_bampton.hpp"

#include <Eigen/SparseCholesky>
#include <Spectra/MatOp/SparseCholesky.h>
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsSolver.h>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numeric>

#include "compensated.hpp"

namespace mbgc::fe {
namespace {

using Triplet = Eigen::Triplet<double, long>;

Eigen::Matrix3d skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d s;
  s << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return s;
}

// The map T from the reduction's coordinates to the FE DOFs, q = T q'. The
// coordinates are the DOFs of nodes in no interface (in FE order), then 6
// per interface: the translation and small rotation of its point. A node of
// an interface moves rigidly with it: u = u_m + theta_m x r, theta = theta_m.
struct Tie {
  SparseMatrix map;   // DOFs x coordinates
  long inner = 0;     // coordinates 0 .. inner-1 are FE DOFs
};

Tie tie_interfaces(const Mesh& mesh, const std::vector<Attachment>& interfaces) {
  const int d = mesh.dofs_per_node;
  std::vector<int> owner(mesh.ids.size(), -1);
  for (std::size_t j = 0; j < interfaces.size(); ++j)
    for (int n : interfaces[j].nodes) owner[static_cast<std::size_t>(n)] = static_cast<int>(j);
  Tie tie;
  std::vector<Triplet> t;
  for (std::size_t n = 0; n < owner.size(); ++n)
    if (owner[n] < 0)
      for (int a = 0; a < d; ++a) t.emplace_back(static_cast<long>(n) * d + a, tie.inner++, 1.0);
  for (std::size_t n = 0; n < owner.size(); ++n) {
    if (owner[n] < 0) continue;
    const Attachment& j = interfaces[static_cast<std::size_t>(owner[n])];
    const long master = tie.inner + 6L * owner[n];
    const Eigen::Matrix3d minus_r = -skew(mesh.position[n] - j.at);  // theta x r = -r x theta
    for (int a = 0; a < 3; ++a) {
      const long row = static_cast<long>(n) * d + a;
      t.emplace_back(row, master + a, 1.0);
      for (int b = 0; b < 3; ++b)
        if (minus_r(a, b) != 0) t.emplace_back(row, master + 3 + b, minus_r(a, b));
      if (d == 6) t.emplace_back(static_cast<long>(n) * d + 3 + a, master + 3 + a, 1.0);
    }
  }
  tie.map.resize(mesh.dofs(), tie.inner + 6L * static_cast<long>(interfaces.size()));
  tie.map.setFromTriplets(t.begin(), t.end());
  return tie;
}

// The coordinates of the reduction without the frame interface's 6: the FE
// DOFs of free nodes, then the other interfaces'. S picks them (rows of T's columns).
SparseMatrix select_columns(long total, const std::vector<long>& keep) {
  SparseMatrix s(total, static_cast<long>(keep.size()));
  std::vector<Triplet> t;
  for (std::size_t k = 0; k < keep.size(); ++k) t.emplace_back(keep[k], static_cast<long>(k), 1.0);
  s.setFromTriplets(t.begin(), t.end());
  return s;
}

}  // namespace

std::optional<Reduction> craig_bampton(const Mesh& mesh, const SparseMatrix& stiffness, const SparseMatrix& mass,
                                       const ReductionRequest& request, ir::Diagnostics& diags) {
  const Tie tie = tie_interfaces(mesh, request.interfaces);
  const long inner = tie.inner;
  std::vector<long> held;  // every coordinate but the frame's 6
  for (long k = 0; k < inner; ++k) held.push_back(k);
  for (std::size_t j = 0; j < request.interfaces.size(); ++j)
    if (static_cast<int>(j) != request.frame)
      for (int a = 0; a < 6; ++a) held.push_back(inner + 6L * static_cast<long>(j) + a);
  const long boundary = static_cast<long>(held.size()) - inner;
  // T restricted to those coordinates; K and M in them.
  const SparseMatrix t = tie.map * select_columns(tie.map.cols(), held);
  const SparseMatrix k = SparseMatrix(t.transpose() * stiffness * t);
  const SparseMatrix m = SparseMatrix(t.transpose() * mass * t);
  const SparseMatrix k_ii = k.topLeftCorner(inner, inner);
  const SparseMatrix m_ii = m.topLeftCorner(inner, inner);

  if (request.normal_modes >= inner) {
    diags.error({}, fmt::format("--modes {}: the model has only {} DOFs inside its interfaces", request.normal_modes, inner),
                "ask for fewer fixed-interface modes");
    return std::nullopt;
  }

  // Constraint modes (eq. 2.219). K_ii = L L^T must exist: the interfaces
  // held, the structure may not move freely or have negative stiffness.
  Eigen::SimplicialLLT<SparseMatrix> k_ii_factor(k_ii);
  if (k_ii_factor.info() != Eigen::Success) {
    diags.error({}, "the stiffness matrix with the interfaces held is not positive definite",
                "an indefinite stiffness matrix, or a part of the mesh that is attached to no interface and can move freely "
                "(check the node order against the matrices and --dofs-per-node)");
    return std::nullopt;
  }
  const int n_normal = request.normal_modes;
  const long n_cms = boundary + n_normal;
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(inner + boundary, n_cms);  // V_CMS (eq. 2.223)
  if (boundary > 0) {
    const Eigen::MatrixXd k_ib = Eigen::MatrixXd(k.topRightCorner(inner, boundary));
    // Two steps of iterative refinement with the residual in long double: a
    // thin solid's K_ii has cond ~ 1e12, and one solve leaves errors of
    // 1e-6 that mix a strip's two bending planes.
    Eigen::MatrixXd psi = k_ii_factor.solve(k_ib);
    const Eigen::SparseMatrix<long double, Eigen::ColMajor, long> k_ii_l = k_ii.cast<long double>();
    const Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic> k_ib_l = k_ib.cast<long double>();
    for (int step = 0; step < 2; ++step) {
      const Eigen::MatrixXd residual = (k_ib_l - k_ii_l * psi.cast<long double>()).cast<double>();
      psi += k_ii_factor.solve(residual);
    }
    v.topLeftCorner(inner, boundary) = -psi;
    v.bottomLeftCorner(boundary, boundary).setIdentity();
  }

  // Fixed-interface normal modes (eq. 2.222) as M_ii v = mu K_ii v, mu = 1/lambda, largest mu first.
  Reduction r;
  r.constraint_modes = static_cast<int>(boundary);
  r.fixed_interface_omega.resize(n_normal);
  if (n_normal > 0) {
    using MassOp = Spectra::SparseSymMatProd<double, Eigen::Lower, Eigen::ColMajor, long>;
    using StiffnessOp = Spectra::SparseCholesky<double, Eigen::Lower, Eigen::ColMajor, long>;
    MassOp mass_op(m_ii);
    StiffnessOp stiffness_op(k_ii);
    const long ncv = std::min<long>(inner, std::max<long>(2L * n_normal + 1, n_normal + 20));
    Spectra::SymGEigsSolver<MassOp, StiffnessOp, Spectra::GEigsMode::Cholesky> eigs(mass_op, stiffness_op, n_normal, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, 10000, 1e-13);
    if (eigs.info() != Spectra::CompInfo::Successful) {
      diags.error({}, fmt::format("the fixed-interface eigenproblem did not converge ({} modes asked)", n_normal),
                  "fewer --modes, or check the mass matrix");
      return std::nullopt;
    }
    const Eigen::VectorXd mu = eigs.eigenvalues();
    const Eigen::MatrixXd vec = eigs.eigenvectors();
    for (int q = 0; q < n_normal; ++q) {
      if (!(mu(q) > 0)) {
        diags.error({}, fmt::format("the model has only {} fixed-interface modes with mass; --modes asks for {}", q, n_normal),
                    "ask for fewer modes, or check the mass matrix (are DOFs massless?)");
        return std::nullopt;
      }
      r.fixed_interface_omega(q) = 1 / std::sqrt(mu(q));
      v.col(boundary + q).head(inner) = vec.col(q);
    }
  }

  // Orthogonalisation (eqs. 2.224–2.225): M_r x = mu K_r x on the reduced pair.
  // K_r compensated, as the file's modal stiffness (invariants.cpp).
  const Eigen::MatrixXd k_r = congruence(k, v);
  Eigen::MatrixXd m_r = v.transpose() * (m * v);
  m_r = (0.5 * (m_r + m_r.transpose())).eval();
  const Eigen::LLT<Eigen::MatrixXd> k_r_factor(k_r);
  if (k_r_factor.info() != Eigen::Success) {
    diags.error({}, "the reduced stiffness matrix is not positive definite",
                "the stiffness matrix is indefinite, or the mesh can move without straining when only the frame interface is held");
    return std::nullopt;
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reduced(m_r, k_r);
  if (reduced.info() != Eigen::Success) {
    diags.error({}, "the reduced eigenproblem (eq. 2.224) did not converge");
    return std::nullopt;
  }
  const int kept = request.keep < 0 ? static_cast<int>(n_cms) : std::min<int>(request.keep, static_cast<int>(n_cms));
  r.omega.resize(kept);
  Eigen::MatrixXd basis(v.rows(), kept);
  for (int q = 0; q < kept; ++q) {
    const long col = n_cms - 1 - q;  // ascending mu: the largest (lowest frequency) last
    const double mu = reduced.eigenvalues()(col);
    if (!(mu > 0)) {
      diags.error({}, fmt::format("reduced mode {} has no mass", q + 1),
                  "an interface whose motion moves no mass; check the mass matrix and the interfaces");
      return std::nullopt;
    }
    r.omega(q) = 1 / std::sqrt(mu);
    basis.col(q) = v * reduced.eigenvectors().col(col);
  }
  r.modes = t * basis;
  // Scale: each mode's largest nodal translation is +1, so eta is a length (m).
  const int d = mesh.dofs_per_node;
  for (int q = 0; q < kept; ++q) {
    double largest = 0;
    for (long row = 0; row < r.modes.rows(); ++row)
      if (row % d < 3 && std::abs(r.modes(row, q)) > std::abs(largest)) largest = r.modes(row, q);
    if (largest != 0) r.modes.col(q) /= largest;
  }
  return r;
}

PointMotion point_motion(const Mesh& mesh, const Attachment& a, const Eigen::MatrixXd& modes) {
  const long n = modes.cols();
  const int d = mesh.dofs_per_node;
  PointMotion p{Eigen::MatrixXd::Zero(3, n), Eigen::MatrixXd::Zero(3, n)};
  if (a.nodes.size() == 1 && mesh.has_rotations()) {
    const long row = static_cast<long>(a.nodes[0]) * d;
    p.shape = modes.middleRows(row, 3);
    p.slope = modes.middleRows(row + 3, 3);
    return p;
  }
  // Least squares: u_s = u + theta x r_s = [I, -skew(r_s)] [u; theta].
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(6, n);
  for (int s : a.nodes) {
    Eigen::Matrix<double, 3, 6> g;
    g << Eigen::Matrix3d::Identity(), -skew(mesh.position[static_cast<std::size_t>(s)] - a.at);
    normal += g.transpose() * g;
    rhs += g.transpose() * modes.middleRows(static_cast<long>(s) * d, 3);
  }
  const Eigen::MatrixXd fit = normal.ldlt().solve(rhs);
  p.shape = fit.topRows(3);
  p.slope = fit.bottomRows(3);
  return p;
}

}  // namespace mbgc::fe
