// Hunt-Crossley's damping for a restitution (runtime/src/contacts.cpp): a
// mass hitting a wall through the force k d^n (1 + chi d'/v-) must leave at
// e v-, whatever k, n, m and v-. Checked here by integrating that contact
// with a hand-written RK4 (independent of SUNDIALS and of the phase-plane
// relation chi was solved from).
#include <gtest/gtest.h>

#include <cmath>

#include "contacts.hpp"

namespace mbgrt::detail {
namespace {

/// The exit speed of a mass m arriving at v- on a Hunt-Crossley wall.
double exit_speed(double e, double k, double n, double m, double v_in) {
  const double chi = hunt_crossley_chi(e);
  double d = 0.0, v = v_in;  // penetration and its rate
  auto accel = [&](double dd, double vv) { return -k / m * std::pow(std::max(dd, 0.0), n) * (1.0 + chi * vv / v_in); };
  // steps of 1/20000 of the time it takes to cross the elastic penetration at v-
  const double depth = std::pow((n + 1) * m * v_in * v_in / (2 * k), 1.0 / (n + 1));
  const double h = depth / v_in / 2e4;
  for (int i = 0; i < 10000000; ++i) {
    const double k1d = v, k1v = accel(d, v);
    const double k2d = v + h / 2 * k1v, k2v = accel(d + h / 2 * k1d, v + h / 2 * k1v);
    const double k3d = v + h / 2 * k2v, k3v = accel(d + h / 2 * k2d, v + h / 2 * k2v);
    const double k4d = v + h * k3v, k4v = accel(d + h * k3d, v + h * k3v);
    const double d_next = d + h / 6 * (k1d + 2 * k2d + 2 * k3d + k4d);
    const double v_next = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (d_next < 0.0 && i > 0) {  // left the wall: the speed where d = 0, by linear interpolation
      const double s = d / (d - d_next);
      return -(v + s * (v_next - v));
    }
    d = d_next;
    v = v_next;
  }
  return NAN;
}

TEST(HuntCrossley, TheDampingGivesTheRestitutionForAnyStiffnessExponentMassAndSpeed) {
  for (double e : {0.1, 0.3, 0.5, 0.8, 0.95, 0.999}) {
    for (auto [k, n, m, v] : {std::tuple{1e6, 1.5, 1.0, 2.0}, std::tuple{1e9, 1.5, 0.01, 0.3}, std::tuple{5e4, 1.0, 3.0, 7.0}}) {
      const double out = exit_speed(e, k, n, m, v);
      EXPECT_NEAR(out / v, e, 1e-7) << "e " << e << ", k " << k << ", n " << n << ", m " << m << ", v " << v;
    }
  }
}

TEST(HuntCrossley, ChiIsZeroForAnElasticContactAndGrowsWithoutBoundAsTheRestitutionVanishes) {
  EXPECT_EQ(hunt_crossley_chi(1.0), 0.0);
  EXPECT_TRUE(std::isinf(hunt_crossley_chi(0.0)));
  double last = 0.0;
  for (double e : {0.99, 0.9, 0.5, 0.1, 0.01, 1e-4}) {
    const double chi = hunt_crossley_chi(e);
    EXPECT_GT(chi, last) << e;
    EXPECT_LT(chi * e, 1.0) << e;  // the force stays a push until the contact opens
    last = chi;
  }
}

}  // namespace
}  // namespace mbgrt::detail
