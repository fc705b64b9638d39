// The integrators' error weights (runtime/src/error_weights.hpp): each
// unknown's absolute tolerance scales with its nominal size, and a vector's
// component is measured relative to at least a tenth of the vector's size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "error_weights.hpp"
#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

/// Five unknowns: a 3-vector (0..2, a light body's momentum, nominal 1e-9)
/// and two loners (3: nominal 1, 4: a nominal that is not a size, as 1).
class Grouped : public Decay {
 public:
  std::size_t size() const override { return 5; }
  double nominal(std::size_t i) const override { return i < 3 ? 1e-9 : i == 3 ? 1.0 : -2.0; }
  std::size_t unknown_group(std::size_t i) const override { return i < 3 ? 0 : i; }
};

TEST(ErrorWeights, AVectorsComponentsShareItsSizeAndEachTakesItsNominal) {
  Grouped m;
  const double rtol = 1e-6, atol = 1e-8;
  detail::ErrorWeights weights(m, rtol, atol);
  const std::vector<double> y = {0.0, 3e-9, 4e-9, -2.0, 0.5};
  std::vector<double> w(5);
  ASSERT_TRUE(weights(y.data(), w.data()));
  // |(0, 3e-9, 4e-9)| = 5e-9: each component is measured against its own size,
  // but never against less than a tenth of its vector's
  EXPECT_DOUBLE_EQ(w[0], 1.0 / (rtol * 5e-10 + atol * 1e-9));
  EXPECT_DOUBLE_EQ(w[1], 1.0 / (rtol * 3e-9 + atol * 1e-9));
  EXPECT_DOUBLE_EQ(w[2], 1.0 / (rtol * 4e-9 + atol * 1e-9));
  EXPECT_DOUBLE_EQ(w[3], 1.0 / (rtol * 2.0 + atol));
  EXPECT_DOUBLE_EQ(w[4], 1.0 / (rtol * 0.5 + atol));
  EXPECT_DOUBLE_EQ(weights.absolute()[0], atol * 1e-9);
}

TEST(ErrorWeights, WithoutGroupsOrNominalsTheyAreSundialsOwn) {
  Decay m;  // one unknown
  detail::ErrorWeights weights(m, 1e-6, 1e-8);
  const double y = -0.25;
  double w = 0.0;
  ASSERT_TRUE(weights(&y, &w));
  EXPECT_EQ(w, 1.0 / (1e-6 * 0.25 + 1e-8));
}

TEST(ErrorWeights, OnceEngagedTheFloorHoldsAtolAtWhatRoundingResolves) {
  // A 3-vector whose size was 2e-3 and is now 1e-12, asked atol 1e-14 x a
  // nominal of 1e-9: 1e-23, far below 1e4 u x 2e-3 = 2.2e-15.
  Grouped m;
  const double rtol = 1e-10, atol = 1e-14, u = std::numeric_limits<double>::epsilon() / 2;
  detail::ErrorWeights weights(m, rtol, atol);
  std::vector<double> w(5);
  const std::vector<double> before = {0.0, 2e-3, 0.0, 1.0, 1.0};
  ASSERT_TRUE(weights(before.data(), w.data()));
  const std::vector<double> now = {0.0, 1e-12, 0.0, 1.0, 1.0};
  ASSERT_TRUE(weights(now.data(), w.data()));
  EXPECT_DOUBLE_EQ(w[1], 1.0 / (rtol * 1e-12 + atol * 1e-9));  // off until engaged
  EXPECT_TRUE(weights.floored().empty());
  weights.engage_floor();
  ASSERT_TRUE(weights(now.data(), w.data()));
  const double floor = detail::ErrorWeights::kRoundingFloor * u * 2e-3;  // the vector's peak, not its size now
  EXPECT_DOUBLE_EQ(w[0], 1.0 / (rtol * 1e-13 + floor));
  EXPECT_DOUBLE_EQ(w[1], 1.0 / (rtol * 1e-12 + floor));
  // a loner of size 1: its floor too, but rtol x 1 sets its tolerance (not named)
  EXPECT_DOUBLE_EQ(w[3], 1.0 / (rtol * 1.0 + detail::ErrorWeights::kRoundingFloor * u * 1.0));
  EXPECT_EQ(weights.floored(), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(ErrorWeights, ANonPositiveToleranceIsRefused) {
  Decay m;
  detail::ErrorWeights weights(m, 0.0, 0.0);
  const double y = 1.0;
  double w = 0.0;
  EXPECT_FALSE(weights(&y, &w));
}

/// Three decaying unknowns: a 2-vector (0, 1) of nominal 1e-9, and a loner.
class SmallVector : public Decay {
 public:
  explicit SmallVector(std::vector<double> y0) : y0_(std::move(y0)) {}
  std::size_t size() const override { return 3; }
  std::string variable_name(std::size_t i) const override { return i == 0 ? "v[0]" : i == 1 ? "v[1]" : "w"; }
  void initial(double, double* y, double*) override { std::copy(y0_.begin(), y0_.end(), y); }
  void derivative(double, const double* y, double* dy) override {
    for (std::size_t i = 0; i < 3; ++i) dy[i] = -p("k") * y[i];
  }
  double nominal(std::size_t i) const override { return i < 2 ? 1e-9 : 1.0; }
  std::size_t unknown_group(std::size_t i) const override { return i < 2 ? 0 : i; }

 private:
  std::vector<double> y0_;
};

TEST(ErrorWeights, TheSummaryNamesStatesWhoseVectorStayedWithinItsAbsoluteTolerance) {
  // atol 1e-8 x nominal 1e-9 = 1e-17: a vector peaking at 5e-16 is resolved
  // only to 2% of it (both components named, the smaller closest) ...
  SmallVector small({5e-16, 2e-16, 1.0});
  RunResult r = run(small, {"--solver", "cvode"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("2 states peaked within 100x their absolute tolerance (closest: 'v[1]', 2e-16 against 1e-17)"),
            std::string::npos)
      << r.err;
  // ... but a component whose vector is large is measured against the vector
  SmallVector mixed({5e-16, 1e-12, 1.0});
  r = run(mixed, {"--solver", "cvode"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("peaked within"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mbgrt::test
