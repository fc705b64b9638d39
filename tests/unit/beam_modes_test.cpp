// Beam modes and modal integrals (flex/beam_modes.hpp) against closed forms:
// the characteristic roots, the boundary conditions, orthonormality, the
// bending stiffness beta^4 L, and the integrals of the pinned–pinned sines
// and the cantilever's classical results.
#include <gtest/gtest.h>

#include <cmath>

#include "flex/beam_modes.hpp"

namespace {

using mbgc::flex::BeamModes;
using mbgc::flex::Supports;
constexpr double kPi = 3.14159265358979323846;
constexpr Supports kAll[] = {Supports::ClampedFree, Supports::PinnedPinned, Supports::ClampedPinned, Supports::FreeFree};

TEST(BeamModes, RootsMatchTheTabulatedValues) {
  // Blevins, Formulas for natural frequency and mode shape, Table 8-1 (beta L)
  const BeamModes cf(Supports::ClampedFree, 1.0, 3), cp(Supports::ClampedPinned, 1.0, 2), ff(Supports::FreeFree, 1.0, 2);
  EXPECT_NEAR(cf.beta_L(0), 1.87510406871196, 1e-12);
  EXPECT_NEAR(cf.beta_L(1), 4.69409113297418, 1e-12);
  EXPECT_NEAR(cf.beta_L(2), 7.85475743823761, 1e-12);
  EXPECT_NEAR(cp.beta_L(0), 3.92660231204792, 1e-12);
  EXPECT_NEAR(cp.beta_L(1), 7.06858274562873, 1e-12);
  EXPECT_NEAR(ff.beta_L(0), 4.73004074486270, 1e-12);
  EXPECT_NEAR(ff.beta_L(1), 7.85320462409584, 1e-12);
  EXPECT_NEAR(BeamModes(Supports::PinnedPinned, 2.0, 3).beta(2), 3 * kPi / 2, 1e-15);
}

TEST(BeamModes, ShapesMeetTheirBoundaryConditions) {
  const double L = 0.61;
  for (Supports s : kAll) {
    const BeamModes m(s, L, 8);
    for (int i = 0; i < m.count(); ++i) {
      // each derivative scaled by beta^k so the conditions compare with O(1)
      auto d = [&](double x, int k) { return m.shape(i, x, k) / std::pow(m.beta(i), k); };
      const double tol = 1e-10;
      switch (s) {
        case Supports::ClampedFree:
          EXPECT_NEAR(d(0, 0), 0, tol); EXPECT_NEAR(d(0, 1), 0, tol);
          EXPECT_NEAR(d(L, 2), 0, tol); EXPECT_NEAR(d(L, 3), 0, tol);
          EXPECT_NEAR(d(L, 0), i % 2 == 0 ? 2 : -2, tol);  // the classical tip value
          break;
        case Supports::PinnedPinned:
        case Supports::ClampedPinned:
          if (s == Supports::PinnedPinned) EXPECT_NEAR(d(0, 2), 0, tol);
          else EXPECT_NEAR(d(0, 1), 0, tol);
          EXPECT_NEAR(d(0, 0), 0, tol);
          EXPECT_NEAR(d(L, 0), 0, tol); EXPECT_NEAR(d(L, 2), 0, tol);
          break;
        case Supports::FreeFree:
          EXPECT_NEAR(d(0, 2), 0, tol); EXPECT_NEAR(d(0, 3), 0, tol);
          EXPECT_NEAR(d(L, 2), 0, tol); EXPECT_NEAR(d(L, 3), 0, tol);
          break;
      }
    }
  }
}

TEST(BeamModes, MassIsOrthonormalAndBendingIsBetaToTheFourth) {
  // int phi_i phi_j = L delta_ij and int phi_i'' phi_j'' = beta_i^4 L delta_ij
  // hold for the exact modes; the quadrature must reproduce them.
  const double L = 8.0;
  for (Supports s : kAll) {
    const BeamModes m(s, L, 6);
    const auto I = mbgc::flex::modal_integrals(m);
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const std::size_t a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
        const double b4 = std::pow(m.beta(i), 4);
        EXPECT_NEAR(I.mass[a][b], i == j ? L : 0, 1e-12 * L) << mbgc::flex::supports_name(s) << " " << i << "," << j;
        EXPECT_NEAR(I.bending[a][b], i == j ? b4 * L : 0, 1e-11 * b4 * L) << mbgc::flex::supports_name(s) << " " << i << "," << j;
      }
  }
}

TEST(BeamModes, PinnedPinnedIntegralsMatchClosedForms) {
  const double L = 0.61;
  const BeamModes m(Supports::PinnedPinned, L, 5);
  const auto I = mbgc::flex::modal_integrals(m);
  for (int i = 0; i < 5; ++i) {
    const std::size_t a = static_cast<std::size_t>(i);
    const double n = i + 1, k = n * kPi / L, c = std::cos(n * kPi);
    EXPECT_NEAR(I.mean[a], std::sqrt(2.0) * L * (1 - c) / (n * kPi), 1e-15);        // sqrt2 int sin kx
    EXPECT_NEAR(I.moment[a], -std::sqrt(2.0) * L * L * c / (n * kPi), 1e-15);       // sqrt2 int x sin kx
    EXPECT_NEAR(I.axial[a][a], k * k * L, 1e-12 * k * k * L);                         // 2 k^2 int cos^2 kx
    EXPECT_NEAR(I.spin[a][a], k * k * L * L * L / 3 - L / 4, 1e-12 * k * k * L * L * L);  // k^2 int (L^2 - x^2) cos^2 kx
    EXPECT_NEAR(I.load[a][a], k * k * L * L / 2, 1e-12 * k * k * L * L);                   // 2 k^2 int (L - x) cos^2 kx
    for (int j = 0; j < 5; ++j)
      if (j != i) {
        EXPECT_NEAR(I.axial[a][static_cast<std::size_t>(j)], 0, 1e-12 * k * k * L);
      }
  }
}

TEST(BeamModes, CantileverMeanMatchesTheClassicalForm) {
  // int_0^L phi_i dx = 2 sigma_i / beta_i for the cantilever modes
  const double L = 8.0;
  const BeamModes m(Supports::ClampedFree, L, 6);
  const auto I = mbgc::flex::modal_integrals(m);
  for (int i = 0; i < 6; ++i) {
    const double B = m.beta_L(i);
    const double sigma = (std::cosh(B) + std::cos(B)) / (std::sinh(B) + std::sin(B));
    EXPECT_NEAR(I.mean[static_cast<std::size_t>(i)], 2 * sigma / m.beta(i), 1e-13 * L) << i;
  }
}

TEST(BeamModes, ForeshorteningIntegralsAreConsistent) {
  // axial, load and spin are a(L), int a dx and int x a dx of the
  // foreshortening a(x) = int_0^x phi' phi'^T: checked by integrating a(x) again.
  const double L = 8.0;
  for (Supports s : kAll) {
    const BeamModes m(s, L, 3);
    const auto I = mbgc::flex::modal_integrals(m);
    const auto aL = mbgc::flex::axial_up_to(m, L);
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j) {
        const double scale = std::abs(I.axial[i][i]) + std::abs(I.axial[j][j]);
        EXPECT_NEAR(aL[i][j], I.axial[i][j], 1e-12 * scale);
        const double load = mbgc::flex::integrate(L, [&](double x) { return mbgc::flex::axial_up_to(m, x)[i][j]; }, 4);
        const double spin = mbgc::flex::integrate(L, [&](double x) { return x * mbgc::flex::axial_up_to(m, x)[i][j]; }, 4);
        EXPECT_NEAR(load, I.load[i][j], 1e-11 * scale * L) << mbgc::flex::supports_name(s);
        EXPECT_NEAR(spin, I.spin[i][j], 1e-11 * scale * L * L) << mbgc::flex::supports_name(s);
      }
    EXPECT_EQ(mbgc::flex::axial_up_to(m, 0)[1][1], 0.0);
  }
}

TEST(BeamModes, CrossMassOfTwoPlanesWithTheSameModesIsTheMassMatrix) {
  const BeamModes a(Supports::ClampedFree, 2.0, 3), b(Supports::ClampedFree, 2.0, 2);
  const auto c = mbgc::flex::cross_mass(a, b);
  ASSERT_EQ(c.size(), 3u);
  ASSERT_EQ(c[0].size(), 2u);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 2; ++j) EXPECT_NEAR(c[i][j], i == j ? 2.0 : 0.0, 1e-12);
}

TEST(BeamModes, QuadratureIsExactForPolynomialsAndAccurateForSmoothFunctions) {
  EXPECT_NEAR(mbgc::flex::integrate(2.0, [](double x) { return std::pow(x, 39); }, 1), std::pow(2.0, 40) / 40, 1e-15 * std::pow(2.0, 40));
  EXPECT_NEAR(mbgc::flex::integrate(kPi, [](double x) { return std::sin(x); }), 2.0, 1e-15);
  EXPECT_NEAR(mbgc::flex::integrate(3.0, [](double x) { return std::exp(x); }), std::exp(3.0) - 1, 1e-13);
}

TEST(BeamModes, SupportNamesRoundTrip) {
  for (Supports s : kAll) {
    Supports back{};
    ASSERT_TRUE(mbgc::flex::supports_from_name(mbgc::flex::supports_name(s), &back));
    EXPECT_EQ(back, s);
  }
  Supports unused{};
  EXPECT_FALSE(mbgc::flex::supports_from_name("clamped_clamped", &unused));
}

}  // namespace

namespace {

TEST(BeamModes, AnchoredModesHoldTheirSectionAndTheirIntegralsAreTakenFromIt) {
  // Free-free modes measured from the section at c = L/2 (frame = centre):
  // zero deflection and slope there, and spin and load (single integrals
  // with by-parts weights) equal the nested integrals int s a_c(s) and
  // int a_c of the signed foreshortening a_c(x) = int_c^x phi' phi'^T.
  const double L = 1.6, c = L / 2;
  const mbgc::flex::BeamModes m = mbgc::flex::BeamModes(mbgc::flex::Supports::FreeFree, L, 3).anchored_at(c);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(m.shape(i, c), 0, 1e-14);
    EXPECT_NEAR(m.shape(i, c, 1), 0, 1e-14);
  }
  const auto I = mbgc::flex::modal_integrals(m);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      auto a = [&](double x) { return mbgc::flex::axial_up_to(m, x)[i][j]; };
      const double load = mbgc::flex::integrate(L, a, 4), spin = mbgc::flex::integrate(L, [&](double x) { return (x - c) * a(x); }, 4);
      EXPECT_NEAR(I.load[i][j], load, 1e-11 * (1 + std::abs(load))) << i << j;
      EXPECT_NEAR(I.spin[i][j], spin, 1e-11 * (1 + std::abs(spin))) << i << j;
    }
}

}  // namespace

namespace {

TEST(BeamModes, InTisserandsFrameTheForeshorteningMovesNoMassAndSpinIsTakenAboutTheCentre) {
  // Free-free modes in Tisserand's frame: unchanged shapes, origin at the
  // mass centre c = L/2, foreshortening a_T(x) = a_c(x) - abar. Its integral
  // (the load, the mass it moves along the beam) must vanish, a_T must differ
  // from a_c by one constant matrix, and spin must be int s a_T(s) ds by
  // nested quadrature; the plain modes' spin about x = 0 must differ from it.
  const double L = 1.6, c = L / 2;
  const BeamModes plain(Supports::FreeFree, L, 3);
  const BeamModes m = plain.in_tisserand_frame();
  EXPECT_EQ(m.origin(), c);
  EXPECT_TRUE(m.mean_free_shortening());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(m.shape(i, 0.3), plain.shape(i, 0.3));
  const auto I = mbgc::flex::modal_integrals(m), P = mbgc::flex::modal_integrals(plain);
  const auto at_quarter = mbgc::flex::axial_up_to(m, L / 4), at_end = mbgc::flex::axial_up_to(m, L);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      auto a = [&](double x) { return mbgc::flex::axial_up_to(m, x)[i][j]; };
      const double load = mbgc::flex::integrate(L, a, 4), spin = mbgc::flex::integrate(L, [&](double x) { return (x - c) * a(x); }, 4);
      const double scale = 1 + std::abs(P.load[i][j]);
      EXPECT_EQ(I.load[i][j], 0.0);
      EXPECT_NEAR(load, 0.0, 1e-11 * scale) << i << j;
      EXPECT_NEAR(I.spin[i][j], spin, 1e-11 * (1 + std::abs(spin))) << i << j;
      // a point's shortening between two sections is that of the plain modes (a_T - a_0 is constant)
      const double plain_between = mbgc::flex::axial_up_to(plain, L)[i][j] - mbgc::flex::axial_up_to(plain, L / 4)[i][j];
      EXPECT_NEAR(at_end[i][j] - at_quarter[i][j], plain_between, 1e-12 * scale) << i << j;
      if (i == j) {
        EXPECT_GT(std::abs(P.spin[i][j] - I.spin[i][j]), 1e-3 * std::abs(I.spin[i][j]));
      }
    }
}

}  // namespace
