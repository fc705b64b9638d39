// reduce_test.cpp — mbgc-reduce (fe/) against the unreduced FE model and the
// closed forms.
//
// The FE models come from make_fe_mesh (fe/make_fe_mesh.cpp), which shares no
// code with the reduction. The unreduced model's frequencies are solved here
// with a dense eigensolver on the clamped matrices (not the reduction's
// Spectra path); the reduced body's are read back from the written file with
// the compiler's own reader, as mbgc will see them.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "compensated.hpp"
#include "flex/modal_file.hpp"
#include "matrix_market.hpp"

namespace {

namespace fs = std::filesystem;
using mbgc::flex::ModalData;

// The bar of all beam cases: 2 m aluminium, 40 mm along y, 30 mm along z.
constexpr double kL = 2, kRho = 2700, kE = 7e10, kWidthY = 0.04, kHeightZ = 0.03;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("mbgc_reduce_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void run(const std::string& command) {
  ASSERT_EQ(std::system((command + " > /dev/null").c_str()), 0) << command;
}

fs::path make_beam(const std::string& name, int elements) {
  const fs::path dir = scratch(name);
  run(std::string(MAKE_FE_MESH) + " beam " + dir.string() + " 2 2700 7e10 0.3 0.04 0.03 " + std::to_string(elements));
  return dir;
}

// Reduces the model in `dir` with `options` and reads the file back.
ModalData reduce(const fs::path& dir, const std::string& options) {
  const fs::path out = dir / "body.mbm";
  const std::string command = std::string(MBGC_REDUCE) + " --stiffness " + (dir / "K.mtx").string() + " --mass " +
                              (dir / "M.mtx").string() + " --nodes " + (dir / "nodes.txt").string() + " " + options +
                              " -o " + out.string();
  EXPECT_EQ(std::system((command + " > /dev/null").c_str()), 0) << command;
  mbgc::ir::SourceManager sources;
  mbgc::ir::Diagnostics diags(sources);
  auto data = mbgc::flex::read_modal_file(out.string(), {}, {}, sources, diags);
  if (!data) {
    diags.render(std::cerr);
    ADD_FAILURE() << "the written file does not read back";
    return {};
  }
  return *data;
}

// The reduced body's frequencies: its modes are orthogonal, omega_k^2 = K_kk / M_kk.
std::vector<double> frequencies(const ModalData& d) {
  std::vector<double> omega;
  for (int k = 0; k < d.count; ++k) {
    const auto& b = d.product_kg[static_cast<std::size_t>(k)][static_cast<std::size_t>(k)];
    omega.push_back(std::sqrt(d.stiffness[static_cast<std::size_t>(k)][static_cast<std::size_t>(k)] / (b[0][0] + b[1][1] + b[2][2])));
  }
  return omega;
}

// v^T A v for a dense symmetric A by Dot2 (fe/compensated.hpp), as mbgc-reduce
// sums its modal stiffness: A v an entry at a time as hi + lo, then
// v^T (hi + lo). Its relative error is u + gamma_{m+1}^2 c to first order
// (m: the most nonzeros in a column, c = |v|^T |A| |v| / v^T A v; the outer
// sum's share, gamma_{2N+1}^2 |v|^T |A v| / v^T A v, is negligible for a
// mode). A plain sum's error, up to n u c, depends on the order of its terms,
// and Eigen's blocking of a dense product follows the CPU's caches.
double quadratic_form(const Eigen::MatrixXd& a, const Eigen::VectorXd& v) {
  mbgc::fe::CompensatedDot form;
  for (long j = 0; j < a.cols(); ++j) {
    mbgc::fe::CompensatedDot row;
    for (long i = 0; i < a.rows(); ++i)
      if (a(i, j) != 0) row.add(a(i, j), v(i));
    const mbgc::fe::DoubleDouble y = row.value();
    form.add(v(j), y.hi);
    form.add(v(j), y.lo);
  }
  return form.value().hi;
}

// The unreduced cantilever: the DOFs of the `clamped` nodes (1-based, node
// file order) removed, K v = lambda M v by a dense solver as M v = mu K v (the
// EB beam's M is singular: no rotary inertia).
std::vector<double> fe_frequencies(const fs::path& dir, int count, int dofs_per_node = 6, std::vector<int> clamped = {1}) {
  mbgc::ir::SourceManager sources;
  mbgc::ir::Diagnostics diags(sources);
  std::ifstream nodes(dir / "nodes.txt");
  long n = 0;
  for (std::string line; std::getline(nodes, line);) n += !line.empty() && line[0] != '#';
  const auto k = mbgc::fe::read_matrix_market((dir / "K.mtx").string(), "K", dofs_per_node * n, sources, diags);
  const auto m = mbgc::fe::read_matrix_market((dir / "M.mtx").string(), "M", dofs_per_node * n, sources, diags);
  EXPECT_TRUE(k && m);
  std::vector<bool> held(static_cast<std::size_t>(n), false);
  for (int c : clamped) held[static_cast<std::size_t>(c - 1)] = true;
  std::vector<long> keep;
  for (long dof = 0; dof < dofs_per_node * n; ++dof)
    if (!held[static_cast<std::size_t>(dof / dofs_per_node)]) keep.push_back(dof);
  const long free = static_cast<long>(keep.size());
  const Eigen::MatrixXd kd(*k), md(*m);
  Eigen::MatrixXd kf(free, free), mf(free, free);
  for (long i = 0; i < free; ++i)
    for (long j = 0; j < free; ++j) kf(i, j) = kd(keep[i], keep[j]), mf(i, j) = md(keep[i], keep[j]);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(mf, kf);
  // Each frequency as its eigenvector's Rayleigh quotient: a solid's K is
  // ill-conditioned (cond ~ 1e12), which leaves the eigenvalue itself with
  // errors of 1e-6; the quotient's error is the square of the vector's.
  std::vector<double> omega;
  for (int q = 0; q < count; ++q) {
    const Eigen::VectorXd v = eig.eigenvectors().col(free - 1 - q);
    omega.push_back(std::sqrt(quadratic_form(kf, v) / quadratic_form(mf, v)));
  }
  return omega;
}

// Euler–Bernoulli cantilever: omega = (beta L)^2 sqrt(E I / (rho A L^4)). Bending
// along z (E Iy) is the softer plane; along y is stiffer by 40/30.
std::vector<double> euler_bernoulli(int count) {
  const double beta_l[] = {1.8751040687119611, 4.6940911329741745, 7.8547574382376126, 10.995540734875467};
  const double area = kWidthY * kHeightZ, iy = kWidthY * std::pow(kHeightZ, 3) / 12, iz = kHeightZ * std::pow(kWidthY, 3) / 12;
  std::vector<double> omega;
  for (double b : beta_l)
    for (double i : {iy, iz}) omega.push_back(b * b * std::sqrt(kE * i / (kRho * area * std::pow(kL, 4))));
  std::sort(omega.begin(), omega.end());
  omega.resize(static_cast<std::size_t>(count));
  return omega;
}

TEST(CompensatedDot, KeepsWhatAPlainSumLoses) {
  // (1 + 2^-30)^2 - (1 + 2^-29) = 2^-60: the first product rounds to
  // 1 + 2^-29, and a plain sum gives 0; TwoProduct keeps the 2^-60.
  mbgc::fe::CompensatedDot products;
  products.add(1 + 0x1p-30, 1 + 0x1p-30);
  products.add(-(1 + 0x1p-29), 1);
  EXPECT_EQ(products.value().hi, 0x1p-60);
  // 1e16 + 1 rounds to 1e16, and a plain sum of 1e16, 1, -1e16 gives 0;
  // TwoSum keeps the 1.
  mbgc::fe::CompensatedDot sum;
  for (double a : {1e16, 1.0, -1e16}) sum.add(a, 1);
  EXPECT_EQ(sum.value().hi, 1);
}

TEST(CraigBampton, FixedInterfaceModesAreTheFEModelsLowestModes) {
  // Root held, no other interface: the reduced body's modes are the FE
  // model's lowest cantilever modes, to the eigensolvers' precision.
  const fs::path dir = make_beam("root_only", 40);
  const ModalData d = reduce(dir, "--interface root=1 --point tip=41 --modes 6");
  ASSERT_EQ(d.count, 6);
  const auto got = frequencies(d), fe = fe_frequencies(dir, 6);
  for (int q = 0; q < 6; ++q) EXPECT_NEAR(got[q], fe[q], 1e-9 * fe[q]) << "mode " << q + 1;
  // the modes are orthogonal in mass and stiffness
  for (int k = 0; k < 6; ++k)
    for (int l = 0; l < 6; ++l) {
      if (k == l) continue;
      const auto& b = d.product_kg[k][l];
      EXPECT_LT(std::abs(b[0][0] + b[1][1] + b[2][2]), 1e-10 * d.mass_kg) << k << " " << l;
      EXPECT_LT(std::abs(d.stiffness[k][l]), 1e-9 * d.stiffness[k][k]) << k << " " << l;
    }
}

TEST(CraigBampton, ATipInterfaceConvergesToTheFEModelFromAbove) {
  // Root held, tip an interface with 6 constraint modes: the orthogonalised
  // basis gives upper bounds (Rayleigh–Ritz) that fall to the FE model's
  // free-tip frequencies as fixed-interface modes are added.
  const fs::path dir = make_beam("root_tip", 40);
  const auto fe = fe_frequencies(dir, 6);
  std::vector<double> previous(6, INFINITY);
  for (int modes : {4, 10, 20}) {
    const auto got = frequencies(reduce(dir, "--interface root=1 --interface tip=41 --keep 6 --modes " + std::to_string(modes)));
    ASSERT_EQ(got.size(), 6u);
    for (int q = 0; q < 6; ++q) {
      EXPECT_GE(got[q], fe[q] * (1 - 1e-12)) << modes << " modes, mode " << q + 1;
      EXPECT_LT(got[q], previous[q]) << modes << " modes, mode " << q + 1;
      previous[q] = got[q];
    }
    if (modes == 20) {  // measured: 1.9e-7 and 3.2e-7 for the two lowest
      for (int q = 0; q < 2; ++q) EXPECT_NEAR(got[q], fe[q], 1e-6 * fe[q]) << "mode " << q + 1;
    }
  }
}

TEST(CraigBampton, TheFEModelConvergesToEulerBernoulli) {
  // The reduced frequencies against the closed form: the error is the FE
  // mesh's (Hermite elements: h^4), so doubling the elements divides it by
  // about 16.
  const auto exact = euler_bernoulli(6);
  std::vector<double> error[2];
  int i = 0;
  for (int elements : {20, 40}) {
    const auto got = frequencies(reduce(make_beam("eb" + std::to_string(elements), elements), "--interface root=1 --modes 6"));
    for (int q = 0; q < 6; ++q) error[i].push_back(std::abs(got[q] / exact[q] - 1));
    ++i;
  }
  for (int q = 0; q < 6; ++q) {
    EXPECT_LT(error[1][q], 2e-6) << "mode " << q + 1 << "; measured 1.0e-6 for the third bending modes with 40 elements";
    std::cout << "mode " << q + 1 << ": relative error " << error[0][q] << " (20 elements), " << error[1][q] << " (40)\n";
    EXPECT_GT(error[0][q] / error[1][q], 14) << "mode " << q + 1 << ": " << error[0][q] << " then " << error[1][q];
  }
}

TEST(CraigBampton, RigidBodyInvariantsAreExact) {
  // mass, first moment and inertia of the bar from its FE mass matrix, about
  // the frame at the root: the element's rigid motions are exact.
  const ModalData d = reduce(make_beam("rigid", 7), "--interface root=1 --modes 3");
  const double m = kRho * kWidthY * kHeightZ * kL;
  EXPECT_NEAR(d.mass_kg, m, 1e-13 * m);
  EXPECT_NEAR(d.first_moment_kg_m[0], m * kL / 2, 1e-13 * m * kL);
  EXPECT_NEAR(d.first_moment_kg_m[1], 0, 1e-13 * m * kL);
  const double polar = kRho * kL * kWidthY * kHeightZ * (kWidthY * kWidthY + kHeightZ * kHeightZ) / 12;
  EXPECT_NEAR(d.inertia_kg_m2[0][0], polar, 1e-12 * polar);            // torsion: rho Ip L
  EXPECT_NEAR(d.inertia_kg_m2[1][1], m * kL * kL / 3, 1e-12 * m);      // line of mass (EB: no rotary inertia of bending)
  EXPECT_NEAR(d.inertia_kg_m2[2][2], m * kL * kL / 3, 1e-12 * m);
  EXPECT_NEAR(d.inertia_kg_m2[0][1], 0, 1e-12 * m);
}

// ---- A mesh without rotations: 20-node bricks, end faces tied to their centroids ----

// The strip of the document's double pendulum (§3.2.4): 0.9 m, 5 mm along y,
// 2 mm along z, steel-like; nu = 0 so that Euler–Bernoulli is its limit.
constexpr double kStripL = 0.9, kStripW = 0.005, kStripH = 0.002, kStripRho = 7850, kStripE = 2.1e11;

fs::path make_strip(const std::string& name, int nx) {
  const fs::path dir = scratch(name);
  run(std::string(MAKE_FE_MESH) + " solid " + dir.string() + " 0.9 7850 2.1e11 0 0.005 0.002 " + std::to_string(nx) + " 1 1");
  return dir;
}

std::vector<int> node_set(const fs::path& file) {
  std::ifstream in(file);
  std::vector<int> ids;
  for (int id; in >> id;) ids.push_back(id);
  return ids;
}

TEST(CraigBamptonSolid, AFaceTiedToTheFrameIsAClampedEnd) {
  // The root face's nodes tied rigidly to the held frame: the body's modes
  // are those of the FE model with that face clamped.
  //
  // Both sides are Rayleigh quotients summed by Dot2 (mbgc-reduce's modal
  // stiffness and quadratic_form here). K has cond 2e12, and the first mode's
  // v^T K v is smaller than |v|^T |K| |v| by c = 1.4e12; Dot2 leaves a
  // relative error of u + gamma_97^2 c = 3e-16 (96 nonzeros a column), which
  // halves in omega. What remains is each vector's own error, squared in its
  // quotient: against a binary128 solution of the same FE model, mode 1's
  // omega is 2.3e-13 high from the dense solver's vector and 2.1e-14 from
  // mbgc-reduce's (measured), the other modes' off by 5e-15 and less. 1e-11
  // leaves a factor 40 over the largest; plain sums in long double missed by
  // 1e-9.
  const fs::path dir = make_strip("solid_root", 40);
  const ModalData d = reduce(dir, "--dofs-per-node 3 --interface root=@" + (dir / "root.txt").string() + " --modes 6");
  const auto got = frequencies(d), fe = fe_frequencies(dir, 6, 3, node_set(dir / "root.txt"));
  for (int q = 0; q < 6; ++q) EXPECT_NEAR(got[q], fe[q], 1e-11 * fe[q]) << "mode " << q + 1;
}

TEST(CraigBamptonSolid, ATipFaceInterfaceConvergesFromAbove) {
  const fs::path dir = make_strip("solid_tip", 40);
  const auto fe = fe_frequencies(dir, 4, 3, node_set(dir / "root.txt"));
  std::vector<double> previous(4, INFINITY);
  for (int modes : {4, 10, 20}) {
    const auto got = frequencies(reduce(dir, "--dofs-per-node 3 --interface root=@" + (dir / "root.txt").string() +
                                                 " --interface tip=@" + (dir / "tip.txt").string() + " --keep 4 --modes " +
                                                 std::to_string(modes)));
    for (int q = 0; q < 4; ++q) {
      EXPECT_GE(got[q], fe[q] * (1 - 1e-12)) << modes << " modes, mode " << q + 1;
      EXPECT_LT(got[q], previous[q]) << modes << " modes, mode " << q + 1;
      previous[q] = got[q];
    }
    if (modes == 20) {
      for (int q = 0; q < 2; ++q) EXPECT_NEAR(got[q], fe[q], 1e-6 * fe[q]) << "mode " << q + 1;
    }
  }
}

TEST(CraigBamptonSolid, TheBricksConvergeToEulerBernoulli) {
  // Flapwise (along z, the 2 mm side) and edgewise bending of the strip against
  // the closed form; the bricks' error falls as the mesh is refined along x.
  const double area = kStripW * kStripH, iy = kStripW * std::pow(kStripH, 3) / 12, iz = kStripH * std::pow(kStripW, 3) / 12;
  const double beta_l[] = {1.8751040687119611, 4.6940911329741745};
  const double exact[3] = {beta_l[0] * beta_l[0] * std::sqrt(kStripE * iy / (kStripRho * area * std::pow(kStripL, 4))),
                           beta_l[0] * beta_l[0] * std::sqrt(kStripE * iz / (kStripRho * area * std::pow(kStripL, 4))),
                           beta_l[1] * beta_l[1] * std::sqrt(kStripE * iy / (kStripRho * area * std::pow(kStripL, 4)))};
  std::vector<double> error[2];
  int i = 0;
  for (int nx : {15, 30}) {
    const fs::path dir = make_strip("solid_eb" + std::to_string(nx), nx);
    const auto got = frequencies(reduce(dir, "--dofs-per-node 3 --interface root=@" + (dir / "root.txt").string() + " --modes 3"));
    for (int q = 0; q < 3; ++q) error[i].push_back(std::abs(got[q] / exact[q] - 1));
    ++i;
  }
  for (int q = 0; q < 3; ++q) {
    std::cout << "mode " << q + 1 << ": relative error " << error[0][q] << " (15 elements), " << error[1][q] << " (30)\n";
    EXPECT_LT(error[1][q], error[0][q]) << "mode " << q + 1;
    EXPECT_LT(error[1][q], 2e-3) << "mode " << q + 1 << "; measured 2.1e-4, 1.5e-4 and 1.4e-3 with 30 elements";
  }
}

TEST(CraigBamptonSolid, InvariantsOfBricksAreExact) {
  // With translations only and M = M_s (x) I_3 every invariant is exact: the
  // file says so, and the rigid-body ones equal the box's closed forms about
  // the root face's centre.
  const fs::path dir = make_strip("solid_invariants", 6);
  const ModalData d = reduce(dir, "--dofs-per-node 3 --interface root=@" + (dir / "root.txt").string() + " --modes 3");
  std::ifstream file(dir / "body.mbm");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("inertia invariants: exact"), std::string::npos);
  const double m = kStripRho * kStripL * kStripW * kStripH;
  EXPECT_NEAR(d.mass_kg, m, 1e-13 * m);
  EXPECT_NEAR(d.first_moment_kg_m[0], m * kStripL / 2, 1e-13 * m * kStripL);
  const double jx = m * (kStripW * kStripW + kStripH * kStripH) / 12;
  const double jy = m * (kStripL * kStripL / 3 + kStripH * kStripH / 12), jz = m * (kStripL * kStripL / 3 + kStripW * kStripW / 12);
  EXPECT_NEAR(d.inertia_kg_m2[0][0], jx, 1e-11 * jx);
  EXPECT_NEAR(d.inertia_kg_m2[1][1], jy, 1e-12 * jy);
  EXPECT_NEAR(d.inertia_kg_m2[2][2], jz, 1e-12 * jz);
}

}  // namespace
