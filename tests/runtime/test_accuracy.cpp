// --accuracy: a run that picks its own method (runtime/src/accuracy.hpp),
// on models whose solutions are known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

/// "0.001", "1e-06": as the summary prints a tolerance ({:g}).
std::string fmt_g(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

/// The largest |x - exact(t)| over the rows, relative to the largest |exact|.
template <class Exact>
double relative_error(const RunResult& r, const char* column, Exact exact) {
  const Csv csv = parse_csv(r.csv);
  double worst = 0, peak = 0;
  for (std::size_t k = 0; k < csv.rows.size(); ++k) {
    const double t = csv.rows[k][0];
    worst = std::max(worst, std::abs(csv.at(k, column) - exact(t)));
    peak = std::max(peak, std::abs(exact(t)));
  }
  return worst / peak;
}

TEST(Accuracy, TheChosenRunMeetsTheRequestAgainstTheClosedForm) {
  for (double tolerance : {1e-3, 1e-6}) {
    Oscillator m;  // 10 s, five periods of omega = 2 ... 50 radians
    RunResult r = run(m, {"--accuracy", std::to_string(tolerance)});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_LT(relative_error(r, "x", [](double t) { return std::cos(2 * t); }), tolerance) << r.err;
    EXPECT_TRUE(Contains(r.err, "  accuracy     asked " + fmt_g(tolerance) + ": chose ")) << r.err;
    EXPECT_TRUE(Contains(r.err, "settings run over the whole run that meet it")) << r.err;
  }
}

TEST(Accuracy, ATighterRequestCostsMoreSteps) {
  Oscillator loose, tight;
  RunResult a = run(loose, {"--accuracy", "1e-3"}), b = run(tight, {"--accuracy", "1e-8"});
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_LT(summary_number(a.err, "evaluations"), summary_number(b.err, "evaluations")) << a.err << b.err;
}

TEST(Accuracy, ARequestNoSettingMeetsStopsWithTheBestItCouldDo) {
  Oscillator m;
  RunResult r = run(m, {"--accuracy", "1e-15"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(Contains(r.err, "--accuracy 1e-15: no setting tried meets it; the most accurate")) << r.err;
  EXPECT_TRUE(r.csv.empty()) << "no rows for a run that was not made";
}

TEST(Accuracy, ChoosesTheSolverSoItIsNotGivenBesideIt) {
  Oscillator a, b;
  RunResult r = run(a, {"--accuracy", "1e-4", "--solver", "rk4"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "give --accuracy or those, not both")) << r.err;
  r = run(b, {"--accuracy", "0"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "--accuracy must be a positive relative error")) << r.err;
}

TEST(Accuracy, TheModelsOwnAccuracyGivesWayToASolverOnTheCommandLine) {
  Oscillator m;
  m.settings.accuracy = 1e-4;
  RunResult chosen = run(m, {});
  ASSERT_EQ(chosen.status, 0) << chosen.err;
  EXPECT_TRUE(Contains(chosen.err, "  accuracy     asked 0.0001")) << chosen.err;
  RunResult by_hand = run(m, {"--solver", "rk4"});
  ASSERT_EQ(by_hand.status, 0) << by_hand.err;
  EXPECT_EQ(by_hand.err.find("  accuracy"), std::string::npos) << by_hand.err;
}

}  // namespace
}  // namespace mbgrt::test
