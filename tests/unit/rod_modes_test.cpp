// Axial and torsion modes (flex/rod_modes.hpp) against closed forms: the end
// conditions, orthonormality (1/L) int chi_i chi_j = delta_ij, the stiffness
// int chi_i' chi_j' = (k_i L)^2 / L delta_ij, and the mean and moment integrals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "flex/rod_modes.hpp"

namespace {

using mbgc::flex::RodEnds;
using mbgc::flex::RodModes;
constexpr double kPi = std::numbers::pi;

TEST(RodModes, EndConditionsHold) {
  const double L = 2.5;
  const RodModes ff(RodEnds::FixedFree, L, 3), xx(RodEnds::FixedFixed, L, 3), fr(RodEnds::FreeFree, L, 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(ff.shape(i, 0), 0, 1e-15);
    EXPECT_NEAR(ff.shape(i, L, 1), 0, 1e-13);  // free end: no strain
    EXPECT_NEAR(xx.shape(i, 0), 0, 1e-15);
    EXPECT_NEAR(xx.shape(i, L), 0, 1e-14);
    EXPECT_NEAR(fr.shape(i, 0, 1), 0, 1e-15);
    EXPECT_NEAR(fr.shape(i, L, 1), 0, 1e-13);
  }
  EXPECT_NEAR(ff.k_L(0), kPi / 2, 1e-15);
  EXPECT_NEAR(ff.k_L(2), 5 * kPi / 2, 1e-15);
  EXPECT_NEAR(xx.k_L(1), 2 * kPi, 1e-15);
  EXPECT_NEAR(fr.k_L(0), kPi, 1e-15);
}

TEST(RodModes, IntegralsMatchTheirClosedForms) {
  const double L = 1.7;
  for (RodEnds e : {RodEnds::FixedFree, RodEnds::FixedFixed, RodEnds::FreeFree}) {
    const RodModes m(e, L, 4);
    const auto I = mbgc::flex::rod_integrals(m);
    for (int i = 0; i < 4; ++i) {
      const double k = m.k_L(i) / L;
      for (int j = 0; j < 4; ++j) {
        EXPECT_NEAR(I.mass[i][j], i == j ? L : 0.0, 1e-13) << mbgc::flex::rod_ends_name(e);
        EXPECT_NEAR(I.stiffness[i][j], i == j ? k * k * L : 0.0, 1e-11 * k * k) << mbgc::flex::rod_ends_name(e);
      }
      // int sqrt2 sin(kx) = sqrt2 (1 - cos kL) / k; int sqrt2 cos(kx) = sqrt2 sin(kL) / k
      const double mean = e == RodEnds::FreeFree ? std::sqrt(2.0) * std::sin(k * L) / k : std::sqrt(2.0) * (1 - std::cos(k * L)) / k;
      EXPECT_NEAR(I.mean[i], mean, 1e-13);
      // int x sqrt2 sin(kx) = sqrt2 (sin kL - kL cos kL) / k^2; int x sqrt2 cos(kx) = sqrt2 (cos kL + kL sin kL - 1) / k^2
      const double moment = e == RodEnds::FreeFree ? std::sqrt(2.0) * (std::cos(k * L) + k * L * std::sin(k * L) - 1) / (k * k)
                                                   : std::sqrt(2.0) * (std::sin(k * L) - k * L * std::cos(k * L)) / (k * k);
      EXPECT_NEAR(I.moment[i], moment, 1e-13);
    }
  }
}

}  // namespace
