// fe/invariants.cpp
#include "invariants.hpp"

#include <cmath>

#include "compensated.hpp"

namespace mbgc::fe {
namespace {

// X - X^T for the axial vector a = ax(X) = [X23 - X32, X31 - X13, X12 - X21].
Eigen::Matrix3d from_ax(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0, a(2), -a(1), -a(2), 0, a(0), a(1), -a(0), 0;
  return s;
}

// The mass of each direction as one node x node matrix M_s: exact when M =
// M_s (x) I_3, else lumped (diagonal, the nodal masses M T_i averaged over i).
SparseMatrix direction_mass(const Mesh& mesh, const SparseMatrix& mass, const Eigen::MatrixXd& translate, bool& exact) {
  const long nodes = static_cast<long>(mesh.ids.size());
  exact = !mesh.has_rotations();
  if (exact) {
    // every entry couples the same direction, and the three directions agree
    double largest = 0;
    for (long c = 0; c < mass.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(mass, c); it; ++it) largest = std::max(largest, std::abs(it.value()));
    for (long c = 0; c < mass.outerSize() && exact; ++c)
      for (SparseMatrix::InnerIterator it(mass, c); it && exact; ++it) {
        const long r = it.row();
        if (r % 3 != c % 3) exact = std::abs(it.value()) <= 1e-14 * largest;
        else exact = std::abs(it.value() - mass.coeff(r - r % 3, c - c % 3)) <= 1e-12 * largest;
      }
  }
  std::vector<Eigen::Triplet<double, long>> t;
  if (exact) {
    for (long c = 0; c < mass.outerSize(); c += 3)
      for (SparseMatrix::InnerIterator it(mass, c); it; ++it)
        if (it.row() % 3 == 0) t.emplace_back(it.row() / 3, c / 3, it.value());
  } else {
    const Eigen::MatrixXd nodal = mass * translate;  // DOFs x 3
    const int d = mesh.dofs_per_node;
    for (long n = 0; n < nodes; ++n)
      t.emplace_back(n, n, (nodal(n * d, 0) + nodal(n * d + 1, 1) + nodal(n * d + 2, 2)) / 3);
  }
  SparseMatrix ms(nodes, nodes);
  ms.setFromTriplets(t.begin(), t.end());
  return ms;
}

}  // namespace

Invariants inertia_invariants(const Mesh& mesh, const SparseMatrix& mass, const SparseMatrix& stiffness,
                              const Eigen::MatrixXd& modes, const Eigen::Vector3d& origin) {
  const int d = mesh.dofs_per_node;
  const long dofs = mesh.dofs(), nodes = static_cast<long>(mesh.ids.size());
  const int n = static_cast<int>(modes.cols());

  // Rigid-body DOF vectors: translate.col(i) = T_i, rotate.col(i) = R_i.
  Eigen::MatrixXd translate = Eigen::MatrixXd::Zero(dofs, 3), rotate = Eigen::MatrixXd::Zero(dofs, 3);
  Eigen::MatrixXd r0(nodes, 3);  // node positions from the frame origin
  for (long a = 0; a < nodes; ++a) {
    const Eigen::Vector3d r = mesh.position[static_cast<std::size_t>(a)] - origin;
    r0.row(a) = r.transpose();
    for (int i = 0; i < 3; ++i) {
      translate(a * d + i, i) = 1;
      rotate.block(a * d, i, 3, 1) = Eigen::Vector3d::Unit(i).cross(r);
      if (d == 6) rotate(a * d + 3 + i, i) = 1;
    }
  }
  const Eigen::MatrixXd m_t = mass * translate, m_r = mass * rotate, m_phi = mass * modes;

  Invariants inv;
  const Eigen::Matrix3d tt = translate.transpose() * m_t;
  inv.mass = tt.trace() / 3;
  inv.mass_by_axis = tt.diagonal();
  const Eigen::Matrix3d tr = translate.transpose() * m_r;  // T_i^T M R_j = eps_ijk s_k
  inv.first_moment << 0.5 * (tr(1, 2) - tr(2, 1)), 0.5 * (tr(2, 0) - tr(0, 2)), 0.5 * (tr(0, 1) - tr(1, 0));
  inv.inertia = rotate.transpose() * m_r;
  inv.inertia = (0.5 * (inv.inertia + inv.inertia.transpose())).eval();
  inv.mean = translate.transpose() * m_phi;
  const Eigen::MatrixXd coupling = rotate.transpose() * m_phi;  // ax(A_k), 3 x n
  const Eigen::MatrixXd modal_mass = modes.transpose() * m_phi;

  // The parts that need each direction's mass: from M_s (exact or lumped).
  const SparseMatrix ms = direction_mass(mesh, mass, translate, inv.exact_directions);
  // phi[j] (nodes x n): the translation along j of each node per mode
  std::vector<Eigen::MatrixXd> phi(3, Eigen::MatrixXd(nodes, n));
  for (long a = 0; a < nodes; ++a)
    for (int j = 0; j < 3; ++j) phi[static_cast<std::size_t>(j)].row(a) = modes.row(a * d + j);
  std::vector<Eigen::MatrixXd> ms_phi(3);
  for (int j = 0; j < 3; ++j) ms_phi[static_cast<std::size_t>(j)] = ms * phi[static_cast<std::size_t>(j)];

  inv.moment.assign(static_cast<std::size_t>(n), Eigen::Matrix3d::Zero());
  inv.product.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), Eigen::Matrix3d::Zero());
  for (int k = 0; k < n; ++k) {
    Eigen::Matrix3d a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = r0.col(i).dot(ms_phi[static_cast<std::size_t>(j)].col(k));
    // symmetric part from M_s, skew part exact: A - A^T = from_ax(ax(A))
    inv.moment[static_cast<std::size_t>(k)] = 0.5 * (a + a.transpose()) + 0.5 * from_ax(coupling.col(k));
    for (int l = 0; l < n; ++l) {
      Eigen::Matrix3d b;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) b(i, j) = phi[static_cast<std::size_t>(i)].col(k).dot(ms_phi[static_cast<std::size_t>(j)].col(l));
      // the trace (modal mass) exact
      b += Eigen::Matrix3d::Identity() * (modal_mass(k, l) - b.trace()) / 3;
      inv.product[static_cast<std::size_t>(k * n + l)] = b;
    }
  }
  for (int k = 0; k < n; ++k)
    for (int l = k + 1; l < n; ++l) {  // B_lk = B_kl^T exactly
      const Eigen::Matrix3d b = 0.5 * (inv.product[static_cast<std::size_t>(k * n + l)] +
                                       inv.product[static_cast<std::size_t>(l * n + k)].transpose());
      inv.product[static_cast<std::size_t>(k * n + l)] = b;
      inv.product[static_cast<std::size_t>(l * n + k)] = b.transpose();
    }
  // Compensated (compensated.hpp): a thin solid's K has cond ~ 1e12 and
  // more, and the low modes' strain energy is a small difference of large
  // terms. Plain sums leave the strip of reduce_test.cpp off by 1e-6 in
  // double and by 1e-9 in long double, by an amount that depends on the
  // order of the terms; Dot2's bound there is u + gamma_97^2 c = 3e-16
  // (c = 1.4e12, 96 nonzeros in a column of K).
  inv.stiffness = congruence(stiffness, modes);
  return inv;
}

}  // namespace mbgc::fe
