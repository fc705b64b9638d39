// accuracy_test.cpp — --accuracy on five kinds of model: a run that picks
// its own method must meet the request against an independent reference
// run (Dormand-Prince at rtol 1e-12, made here), measured as the runtime
// measures it: the largest |y - y_ref| over the outputs and the rows, each
// output scaled by its largest |y_ref|, but by no less than the model's
// atol / rtol (its --help gives both).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

/// The default of option `name` in a simulator's --help ("--rtol X=1e-06").
double help_default(const std::string& sim, const std::string& name) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(("\"" + sim + "\" --help").c_str(), "r"), pclose);
  std::string text;
  std::array<char, 4096> buf;
  while (pipe && std::fgets(buf.data(), buf.size(), pipe.get())) text += buf.data();
  const auto at = text.find(name + " X=");
  EXPECT_NE(at, std::string::npos) << text;
  return at == std::string::npos ? NAN : std::strtod(text.c_str() + at + name.size() + 3, nullptr);
}

double max_rel_error(const Csv& run, const Csv& ref, double floor) {
  EXPECT_EQ(run.rows.size(), ref.rows.size());
  double worst = 0;
  for (std::size_t c = 1; c < ref.header.size(); ++c) {
    double scale = floor;
    for (const auto& r : ref.rows) scale = std::max(scale, std::abs(r[c]));
    for (std::size_t i = 0; i < std::min(run.rows.size(), ref.rows.size()); ++i)
      worst = std::max(worst, std::abs(run.rows[i][c] - ref.rows[i][c]) / scale);
  }
  return worst;
}

struct Case {
  const char* kind;
  const char* sim;
  const char* options;  ///< the run's length, where the model's is longer than the test needs
};

class AccuracyOf : public ::testing::TestWithParam<Case> {};

TEST_P(AccuracyOf, TheRunItChoosesMeetsTheRequestAgainstAnIndependentReference) {
  const Case& c = GetParam();
  const double floor = help_default(c.sim, "--atol") / help_default(c.sim, "--rtol");
  for (const char* tolerance : {"1e-3", "1e-5"}) {
    SimRun chosen = run(c.sim, std::string(c.options) + " --accuracy " + tolerance, std::string("accuracy_") + c.kind);
    ASSERT_EQ(chosen.status, 0) << chosen.log;
    char atol[32];
    std::snprintf(atol, sizeof atol, "%g", 1e-12 * floor);
    SimRun ref = run(c.sim, std::string(c.options) + " --solver dopri5 --rtol 1e-12 --atol " + atol + " --quiet",
                     std::string("accuracy_ref_") + c.kind);
    ASSERT_EQ(ref.status, 0) << ref.log;
    const double error = max_rel_error(chosen.csv, ref.csv, floor);
    EXPECT_LE(error, std::strtod(tolerance, nullptr)) << c.kind << " at " << tolerance << ":\n" << chosen.log;
    char asked[32];
    std::snprintf(asked, sizeof asked, "%g", std::strtod(tolerance, nullptr));
    EXPECT_NE(chosen.log.find(std::string("  accuracy     asked ") + asked + ": chose "), std::string::npos) << chosen.log;
    RecordProperty(std::string(c.kind) + "_" + tolerance, std::to_string(error));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Examples, AccuracyOf,
    ::testing::Values(Case{"rigid", MB_PENDULUM_COORDINATES_SIM, "--t-end 5"},
                      Case{"flexible", ROTATING_BEAM_COORDINATES_SIM, "--t-end 2"},
                      Case{"stiff", CHAIN2_PENALTY_SIM, "--t-end 2"},
                      Case{"contact", BALL_COMPLIANT_SIM, "--t-end 2"},
                      Case{"vehicle", TWO_TRACK_SIM, "--t-end 4"}),
    [](const auto& info) { return std::string(info.param.kind); });

}  // namespace
