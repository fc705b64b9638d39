// --linearize-at: eigenvalues of the numerical Jacobian as modes,
// checked against systems whose eigenvalues are known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

// Linear models: central differences are exact up to rounding, ~1e-10 relative.
constexpr double kLinearTol = 1e-7;

TEST(Linearize, HeaderIsTheContractOne) {
  Oscillator m(2.0, 0.05);
  RunResult r = run(m, {"--linearize-at", "0"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.csv.substr(0, r.csv.find('\n')), "index,omega_rad_s,f_hz,damping_ratio");
}

TEST(Linearize, DampedOscillatorGivesOmegaAndZeta) {
  const double omega = 2.0, zeta = 0.05;
  Oscillator m(omega, zeta);
  RunResult r = run(m, {"--linearize-at", "3"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 1u) << "a complex pair is one mode";
  EXPECT_EQ(csv.at(0, "index"), 1.0);
  EXPECT_NEAR(csv.at(0, "omega_rad_s"), omega, kLinearTol);
  EXPECT_NEAR(csv.at(0, "f_hz"), omega * std::sqrt(1 - zeta * zeta) / (2 * std::numbers::pi),
              kLinearTol);
  EXPECT_NEAR(csv.at(0, "damping_ratio"), zeta, kLinearTol);
  EXPECT_TRUE(Contains(r.err, "1 modes to"));
}

TEST(Linearize, ModesAreSortedLowestFirstAndRealModesHaveZeroFrequency) {
  ThreeModes m;  // omega 5 (zeta 0.02), omega 2 (zeta 0.1), real eigenvalue -7
  RunResult r = run(m, {"--linearize-at", "0.5"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 3u);
  const double omegas[] = {2.0, 5.0, 7.0}, zetas[] = {0.1, 0.02, 1.0};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(csv.at(i, "index"), static_cast<double>(i + 1));
    EXPECT_NEAR(csv.at(i, "omega_rad_s"), omegas[i], kLinearTol) << i;
    EXPECT_NEAR(csv.at(i, "damping_ratio"), zetas[i], kLinearTol) << i;
  }
  EXPECT_EQ(csv.at(2, "f_hz"), 0.0);
}

TEST(Linearize, JacobianIsTakenAtTheIntegratedState) {
  // x' = -x^3 from x(0) = 1: x(1.5) = 1/2, so the eigenvalue is -3 x^2 = -0.75.
  CubicDecay m;
  RunResult r = run(m, {"--linearize-at", "1.5", "--rtol", "1e-10", "--atol", "1e-12"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 1u);
  // Nonlinear: central-difference truncation ~ h^2 = 1e-12, integration ~ 1e-9.
  EXPECT_NEAR(csv.at(0, "omega_rad_s"), 0.75, 1e-7);
  EXPECT_EQ(csv.at(0, "f_hz"), 0.0);
  EXPECT_NEAR(csv.at(0, "damping_ratio"), 1.0, 1e-12);
}

TEST(Linearize, UndampedModeHasZeroNotNegativeZeroDamping) {
  Oscillator m(3.0, 0.0);
  RunResult r = run(m, {"--linearize-at", "0"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string row = r.csv.substr(r.csv.find('\n') + 1);
  EXPECT_EQ(row.substr(row.rfind(',')), ",0\n");
  EXPECT_NEAR(parse_csv(r.csv).at(0, "omega_rad_s"), 3.0, kLinearTol);
}

TEST(Linearize, DaeModelGivesTheEigenvaluesOnItsConstraints) {
  // x' = -x + z with 0 = z + 2 x: on the constraint x' = -3 x. The pencil
  // (dF/dy, dF/dy') also has an infinite eigenvalue (the algebraic row): dropped.
  SmallDae m;
  RunResult r = run(m, {"--linearize-at", "0.1"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_NEAR(csv.at(0, "omega_rad_s"), 3.0, kLinearTol);
  EXPECT_EQ(csv.at(0, "f_hz"), 0.0);
  EXPECT_NEAR(csv.at(0, "damping_ratio"), 1.0, kLinearTol);
}

/// x' = x from 1, with |x| valid up to 2: the run stops at t = ln 2 with the reason.
class LimitedGrowth : public CubicDecay {
 public:
  const char* name() const override { return "limited_growth"; }
  void derivative(double, const double* y, double* dy) override { dy[0] = y[0]; }
  double state_limit(std::size_t) const override { return 2.0; }
  std::string state_limit_reason(std::size_t) const override { return "the tank overflows"; }
};

TEST(StateLimit, RunStopsWhereAStateLeavesItsModelsRangeAndSaysWhy) {
  LimitedGrowth m;
  RunResult r = run(m, {"--interval", "0.01", "--rtol", "1e-10", "--atol", "1e-12"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "state 'x' = 2.0")) << r.err;
  EXPECT_TRUE(Contains(r.err, "is beyond its limit 2: the tank overflows")) << r.err;
  EXPECT_TRUE(Contains(r.err, "at t = 0.7 s")) << r.err;  // the first output point past ln 2 = 0.693
}

TEST(Linearize, FailureBeforeTheLinearizationTimeExitsOne) {
  DrainingTank m;
  RunResult r = run(m, {"--linearize-at", "1.5", "--solver", "rk4"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.err, "state 'tank.level' became NaN"));
}

}  // namespace
}  // namespace mbgrt::test
