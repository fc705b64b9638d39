// loop_test.cpp — closed loops at their limits (models/slider_crank.mbg, a
// slider-crank driven at 10 rad/s): through its dead centres it follows the
// closed form under every strategy; with a rod shorter than the crank the
// loop cannot close a quarter of a turn in, and every strategy must stop
// there with a report and exit status 1, never write rows of a broken
// mechanism with exit status 0.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

double worst_error(const SimRun& r) {
  double worst = 0.0;
  for (const auto& row : r.csv.rows) worst = std::max(worst, std::abs(row[r.csv.col("x")] - row[r.csv.col("x_exact")]));
  return worst;
}

struct Strategy {
  const char* name;
  const char* sim;
  double tolerance;  ///< of x against the closed form (m)
};

class SliderCrank : public ::testing::TestWithParam<Strategy> {};

}  // namespace

TEST_P(SliderCrank, RunsThroughItsDeadCentresAsTheClosedFormSays) {
  const Strategy& s = GetParam();
  SimRun r = run(s.sim, "", std::string("slider_crank_") + s.name);
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 201u) << r.log;  // 2 s: three turns, six dead centres
  EXPECT_LT(worst_error(r), s.tolerance) << r.log;
}

/// The rod (0.1 m) reaches the axis only while 0.2 sin(10 t) <= 0.1: up to
/// t = asin(0.5) / 10 = 0.05236 s, the dead point where it is perpendicular
/// to the axis. The run must stop soon after, naming the joint that opens.
TEST_P(SliderCrank, WithARodShorterThanTheCrankStopsWhereTheLoopCannotClose) {
  const Strategy& s = GetParam();
  SimRun r = run(s.sim, "--set L=0.1", std::string("slider_crank_short_") + s.name);
  EXPECT_EQ(r.status, 1) << r.log;
  EXPECT_TRUE(contains(r.log, "mbgrt: error: at t = ")) << r.log;
  ASSERT_FALSE(r.csv.rows.empty()) << r.log;
  const double last = r.csv.rows.back()[0];
  EXPECT_GT(last, 0.04) << r.log;  // it ran up to the dead point
  EXPECT_LT(last, 0.2) << r.log;   // and stopped soon after it
  for (const auto& row : r.csv.rows)
    for (double v : row) ASSERT_TRUE(std::isfinite(v)) << "t = " << row[0];
  if (std::string(s.name) == "coordinates") {
    EXPECT_TRUE(contains(r.log, "joint row j3.cn[")) << r.log;
    EXPECT_TRUE(contains(r.log, "a loop that cannot close")) << r.log;
    EXPECT_TRUE(contains(r.log, "the cut joints' rows first became dependent at t = 0.0523")) << r.log;
  } else if (std::string(s.name) == "penalty") {
    EXPECT_TRUE(contains(r.log, "penalty joint row")) << r.log;
  } else {
    EXPECT_TRUE(contains(r.log, "the joints' constraint rows are close to losing rank")) << r.log;
  }
}

/// Started where the loop cannot close (the crank at 90 degrees), nothing runs.
TEST_P(SliderCrank, StartedWhereTheLoopCannotCloseAssemblyFails) {
  const Strategy& s = GetParam();
  SimRun r = run(s.sim, "--set L=0.1 --set th0=1.5708", std::string("slider_crank_start_") + s.name);
  EXPECT_EQ(r.status, 1) << r.log;
  EXPECT_TRUE(contains(r.log, "assembly failed: constraint `j")) << r.log;
  EXPECT_TRUE(contains(r.log, "the joints cannot all be closed")) << r.log;
  EXPECT_TRUE(r.csv.rows.empty()) << r.log;
}

INSTANTIATE_TEST_SUITE_P(Strategies, SliderCrank,
                         ::testing::Values(Strategy{"coordinates", SLIDER_CRANK_SIM, 1e-7},
                                           // a penalty joint gives F / k (the driven crank's row
                                           // lags by 8.8e-5 rad): measured 3.7e-4 m
                                           Strategy{"penalty", SLIDER_CRANK_PENALTY_SIM, 1e-3},
                                           Strategy{"lagrange", SLIDER_CRANK_LAGRANGE_SIM, 1e-7}),
                         [](const ::testing::TestParamInfo<Strategy>& info) { return std::string(info.param.name); });
