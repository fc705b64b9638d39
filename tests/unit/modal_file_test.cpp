// Modal-data files (flex/modal_file.hpp): the reader on a written file, and
// the mass-matrix coefficients from the invariants against the kinetic
// energy of a cloud of point masses summed directly, for a general 3-D
// displacement field (every component of r0 and of the modes nonzero).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "flex/modal_file.hpp"

namespace {

using mbgc::flex::Matrix;
using mbgc::flex::ModalData;
using Vec = std::array<double, 3>;

Vec cross(const Vec& a, const Vec& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Point masses with a linear field u_i = Phi_i eta: the "FE model".
struct Cloud {
  int n = 3;
  std::vector<double> m;
  std::vector<Vec> r0;
  std::vector<std::vector<Vec>> phi;  // phi[i][k]: mode k at mass i
  Vec r(std::size_t i, const std::vector<double>& eta) const {
    Vec x = r0[i];
    for (std::size_t k = 0; k < eta.size(); ++k)
      for (int a = 0; a < 3; ++a) x[static_cast<std::size_t>(a)] += phi[i][k][static_cast<std::size_t>(a)] * eta[k];
    return x;
  }
  /// The invariants of docs/modal_format.md, summed over the masses.
  ModalData invariants() const {
    ModalData d;
    d.count = n;
    const auto N = static_cast<std::size_t>(n);
    auto zeros = [](std::size_t r, std::size_t c) { return Matrix(r, std::vector<double>(c, 0.0)); };
    d.inertia_kg_m2 = zeros(3, 3), d.mean_kg = zeros(3, N), d.stiffness = zeros(N, N);
    d.moment_kg_m.assign(N, zeros(3, 3));
    d.product_kg.assign(N, std::vector<Matrix>(N, zeros(3, 3)));
    for (std::size_t i = 0; i < m.size(); ++i) {
      d.mass_kg += m[i];
      for (std::size_t a = 0; a < 3; ++a) {
        d.first_moment_kg_m[a] += m[i] * r0[i][a];
        for (std::size_t b = 0; b < 3; ++b) d.inertia_kg_m2[a][b] += m[i] * ((a == b ? dot(r0[i], r0[i]) : 0.0) - r0[i][a] * r0[i][b]);
        for (std::size_t k = 0; k < N; ++k) {
          d.mean_kg[a][k] += m[i] * phi[i][k][a];
          for (std::size_t b = 0; b < 3; ++b) {
            d.moment_kg_m[k][a][b] += m[i] * r0[i][a] * phi[i][k][b];
            for (std::size_t l = 0; l < N; ++l) d.product_kg[k][l][a][b] += m[i] * phi[i][k][a] * phi[i][l][b];
          }
        }
      }
    }
    return d;
  }
};

Cloud random_cloud(unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Cloud c;
  for (int i = 0; i < 9; ++i) {
    c.m.push_back(1 + u(gen) * 0.5);
    c.r0.push_back({u(gen) + 1, u(gen), u(gen)});
    std::vector<Vec> modes;
    for (int k = 0; k < c.n; ++k) modes.push_back({u(gen) * 0.3, u(gen), u(gen)});
    c.phi.push_back(modes);
  }
  return c;
}

TEST(ModalMassTerms, KineticEnergyOfAGeneralFieldEqualsTheDirectSumOverMasses) {
  const Cloud c = random_cloud(7);
  const ModalData d = c.invariants();
  const auto t = mbgc::flex::modal_mass_terms(d);
  const auto N = static_cast<std::size_t>(c.n);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> eta(N), etadot(N);
    for (auto& x : eta) x = 0.4 * u(gen);
    for (auto& x : etadot) x = u(gen);
    const Vec V = {u(gen), u(gen), u(gen)}, w = {u(gen), u(gen), u(gen)};
    // direct: 1/2 sum m |V + w x r + Phi etadot|^2
    double T_direct = 0;
    for (std::size_t i = 0; i < c.m.size(); ++i) {
      Vec v = V;
      const Vec wr = cross(w, c.r(i, eta));
      for (std::size_t a = 0; a < 3; ++a) {
        v[a] += wr[a];
        for (std::size_t k = 0; k < N; ++k) v[a] += c.phi[i][k][a] * etadot[k];
      }
      T_direct += 0.5 * c.m[i] * dot(v, v);
    }
    // from the terms: M assembled as docs/modal_format.md says
    Vec s = d.first_moment_kg_m;
    for (std::size_t a = 0; a < 3; ++a)
      for (std::size_t k = 0; k < N; ++k) s[a] += d.mean_kg[a][k] * eta[k];
    double J[3][3];
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j) {
        J[i][j] = d.inertia_kg_m2[i][j];
        for (std::size_t k = 0; k < N; ++k) {
          J[i][j] += t.J1[i][j][0][k] * eta[k];
          for (std::size_t l = 0; l < N; ++l) J[i][j] += t.J2[i][j][k][l] * eta[k] * eta[l];
        }
      }
    double T = 0.5 * d.mass_kg * dot(V, V) + dot(V, cross(w, s));  // M_VV and the V-omega blocks (-skew(s))
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j) T += 0.5 * w[i] * J[i][j] * w[j];
    for (std::size_t l = 0; l < N; ++l) {
      for (std::size_t a = 0; a < 3; ++a) {
        T += V[a] * d.mean_kg[a][l] * etadot[l];
        double c_al = t.coupling[a][0][l];
        for (std::size_t k = 0; k < N; ++k) c_al += t.coupling_eta[a][k][l] * eta[k];
        T += w[a] * c_al * etadot[l];
      }
      for (std::size_t k = 0; k < N; ++k) T += 0.5 * etadot[k] * t.modal_mass[k][l] * etadot[l];
    }
    EXPECT_NEAR(T, T_direct, 1e-12 * T_direct) << "trial " << trial;
  }
  // J2 is symmetric in (k, l), J1 and J2 symmetric in (i, j)
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t k = 0; k < N; ++k) {
        EXPECT_DOUBLE_EQ(t.J1[i][j][0][k], t.J1[j][i][0][k]);
        for (std::size_t l = 0; l < N; ++l) EXPECT_NEAR(t.J2[i][j][k][l], t.J2[i][j][l][k], 1e-15);
      }
}

TEST(ModalFile, ReadsWhatWasWrittenAndFillsTheTransposedProducts) {
  const Cloud c = random_cloud(3);
  const ModalData d = c.invariants();
  const std::string path = ::testing::TempDir() + "modal_file_test.mbm";
  {
    std::ofstream out(path);
    out.precision(17);
    auto put = [&](const Matrix& m) {
      for (const auto& r : m)
        for (double x : r) out << ' ' << x;
      out << '\n';
    };
    out << "# written by modal_file_test\nmbgc_modal_body 1\nmodes " << d.count << "\nmass " << d.mass_kg << "\nfirst_moment";
    put({{d.first_moment_kg_m[0], d.first_moment_kg_m[1], d.first_moment_kg_m[2]}});
    out << "inertia";
    put(d.inertia_kg_m2);
    out << "mean";
    put(d.mean_kg);
    for (int k = 0; k < d.count; ++k) {
      out << "moment " << k + 1;
      put(d.moment_kg_m[static_cast<std::size_t>(k)]);
      for (int l = k; l < d.count; ++l) {
        out << "product " << k + 1 << ' ' << l + 1;
        put(d.product_kg[static_cast<std::size_t>(k)][static_cast<std::size_t>(l)]);
      }
    }
    out << "stiffness 100 0 0  0 200 0  0 0 300\npoint tip 1 2 3\nshape tip";
    put(Matrix(3, std::vector<double>(3, 0.5)));
    out << "slope tip";
    put(Matrix(3, std::vector<double>(3, -0.25)));
  }
  mbgc::ir::SourceManager sources;
  mbgc::ir::Diagnostics diags(sources);
  auto read = mbgc::flex::read_modal_file(path, {}, {}, sources, diags);
  ASSERT_TRUE(read.has_value());
  EXPECT_FALSE(diags.has_errors());
  EXPECT_EQ(read->count, 3);
  EXPECT_DOUBLE_EQ(read->mass_kg, d.mass_kg);
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t l = 0; l < 3; ++l)
      for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b)  // k > l: the transpose of what was written; k = l symmetrised
          EXPECT_EQ(read->product_kg[k][l][a][b], k < l ? d.product_kg[k][l][a][b]
                                                  : k > l ? d.product_kg[l][k][b][a]
                                                          : 0.5 * (d.product_kg[k][k][a][b] + d.product_kg[k][k][b][a]));
  EXPECT_DOUBLE_EQ(read->stiffness[2][2], 300);
  ASSERT_EQ(read->points.count("tip"), 1u);
  EXPECT_DOUBLE_EQ(read->points.at("tip").position[2], 3);
  EXPECT_DOUBLE_EQ(read->points.at("tip").slope[1][2], -0.25);
  EXPECT_EQ(sources.count(), 1) << "the file joins the sources (diagnostics, depfile)";
  std::remove(path.c_str());
}

}  // namespace
