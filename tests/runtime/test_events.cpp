// Events with jumps (Model::event_jump): a ball dropped on a floor, its
// impacts as events whose jump is Newton's restitution law v+ = -e v-, the
// unilateral contact of issue 16 in its simplest form, written by hand. Its
// impact times and apex heights are known in closed form: after impact k the
// speed is e^k v1 (v1 = sqrt(2 g h)), the apex e^(2k) h, the next impact
// 2 e^k v1 / g later. Once an impact is slower than the model's resting
// speed the ball rests (Zeno's bouncing would never end): the model holds it
// on the floor and says so through its event's name.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

constexpr double kG = 9.81;

class BouncingBall : public TestModel {
 public:
  BouncingBall() {
    param("h0", 1.0);
    param("e", 0.8);
    param("v_rest", 1e-3);  // m/s: an impact slower than this ends the bouncing
    settings.t_end_s = 5.0;
    settings.interval_s = 0.01;
    settings.rtol = 1e-10;
    settings.atol = 1e-12;
  }
  const char* name() const override { return "bouncing_ball"; }
  std::size_t size() const override { return 2; }
  std::string variable_name(std::size_t i) const override { return i == 0 ? "ball.gap" : "ball.v"; }
  std::vector<std::string> output_names() const override { return {"gap", "v", "apex"}; }
  void initial(double, double* y, double*) override {
    y[0] = p("h0");
    y[1] = 0.0;
    resting_ = false;
  }
  void derivative(double, const double* y, double* dy) override {
    dy[0] = resting_ ? 0.0 : y[1];
    dy[1] = resting_ ? 0.0 : -kG;  // resting: the floor's normal force is m g
  }
  void outputs(double, const double* y, const double*, double* out) override {
    out[0] = y[0];
    out[1] = y[1];
    out[2] = y[0] + y[1] * y[1] / (2 * kG);  // the height this flight reaches
  }
  std::size_t event_count() const override { return 1; }
  void event_functions(double, const double* y, const double*, double* g) override { g[0] = resting_ ? 1.0 : y[0]; }
  std::string event_name(std::size_t) const override { return "ball.floor"; }
  bool set_event_mode(std::size_t, bool on) override {
    if (free_ == on) return false;
    free_ = on;
    return true;
  }
  // The impact: the ball on the floor (its gap at 0, not at the rounding
  // level where the root was found, so that the next crossing is seen from
  // the right side), leaving at e times the speed it came with, free again;
  // or resting, if that is slower than v_rest.
  bool event_jump(std::size_t, bool on, double, double* y) override {
    if (on || y[1] >= 0.0) return false;  // lift-off, or already leaving
    y[0] = 0.0;
    y[1] = -p("e") * y[1];
    if (y[1] < p("v_rest")) {
      y[1] = 0.0;
      resting_ = true;
    } else {
      free_ = true;
    }
    return true;
  }

 private:
  bool free_ = true;
  bool resting_ = false;
};

/// Impact k (from 0) in closed form.
double impact_time(int k, double h, double e) {
  const double v1 = std::sqrt(2 * kG * h);
  double t = v1 / kG;
  for (int i = 1; i <= k; ++i) t += 2 * std::pow(e, i) * v1 / kG;
  return t;
}

class EventJumps : public ::testing::TestWithParam<const char*> {};

TEST_P(EventJumps, ABouncingBallsImpactsAndApexesAreTheClosedForms) {
  BouncingBall ball;
  const std::string solver = GetParam();
  const std::string log = temp_path("bounces.csv");
  std::vector<std::string> args{"--solver", solver, "--event-log", log};
  if (solver == "rk4") args.insert(args.end(), {"--step", "1e-3"});
  RunResult r = run(ball, args);
  ASSERT_EQ(r.status, 0) << r.err;
  // Impacts are the switches to off (the gap went through 0 downwards).
  const std::string text = read_file(log);
  std::vector<double> impacts;
  std::size_t line = text.find('\n') + 1;  // after the header t,event,name,state,jump,note
  while (line < text.size()) {
    const std::size_t end = text.find('\n', line);
    const std::string row = text.substr(line, end - line);
    if (row.ends_with(",off,1,\"\"")) impacts.push_back(std::stod(row.substr(0, row.find(','))));
    line = end + 1;
  }
  ASSERT_GE(impacts.size(), 10u) << text;
  const double e = 0.8, h = 1.0;
  for (int k = 0; k < 10; ++k)
    EXPECT_NEAR(impacts[static_cast<std::size_t>(k)], impact_time(k, h, e), 1e-8 * impact_time(k, h, e)) << solver << ", impact " << k;
  // Apexes: between impacts k - 1 and k, the height reached is e^(2k) h.
  const Csv out = parse_csv(r.csv);
  int checked = 0;
  for (std::size_t i = 0; i < out.rows.size(); ++i) {
    const double t = out.rows[i][0];
    int k = 0;
    while (k < 10 && impact_time(k, h, e) < t) ++k;
    if (k == 0 || k >= 10 || std::abs(t - impact_time(k - 1, h, e)) < 1e-6 || std::abs(t - impact_time(k, h, e)) < 1e-6) continue;
    EXPECT_NEAR(out.at(i, "apex"), std::pow(e, 2 * k) * h, 1e-8) << solver << " at t = " << t;
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // The bouncing ends at the impact k whose rebound e^(k+1) v1 would be
  // slower than v_rest, as the closed form says, and the ball rests after it.
  const double v1 = std::sqrt(2 * kG * h);
  const auto last = static_cast<std::size_t>(std::ceil(std::log(1e-3 / v1) / std::log(e))) - 1;
  EXPECT_EQ(impacts.size(), last + 1) << text;
  EXPECT_NEAR(impacts.back(), impact_time(static_cast<int>(last), h, e), 1e-6) << solver;
  EXPECT_EQ(out.rows.back()[out.column("gap")], 0.0);
  EXPECT_EQ(out.rows.back()[out.column("v")], 0.0);
  EXPECT_TRUE(Contains(r.err, "ball.floor off, jump"));
  EXPECT_TRUE(Contains(r.err, "(--event-log FILE.csv writes them all)"));
}

INSTANTIATE_TEST_SUITE_P(Solvers, EventJumps, ::testing::Values("rk4", "dopri5", "cvode", "ida"));

TEST_P(EventJumps, ZenosBouncingWithoutARestingSpeedStopsWithADiagnosisNotAHang) {
  BouncingBall ball;  // v_rest = 0: it never rests, its impacts accumulate at t = 4.06 s
  const std::string solver = GetParam();
  std::vector<std::string> args{"--solver", solver, "--set", "v_rest=0"};
  if (solver == "rk4") args.insert(args.end(), {"--step", "1e-3"});
  RunResult r = run(ball, args);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(Contains(r.err, "events accumulate (Zeno): `ball.floor` switched 11 times in a row")) << r.err;
  // ... just before the closed form's accumulation point v1/g (1 + 2e/(1 - e)).
  const double v1 = std::sqrt(2 * kG * 1.0), t_inf = v1 / kG * (1 + 2 * 0.8 / (1 - 0.8));
  EXPECT_LT(reported_time(r.err), t_inf);
  EXPECT_NEAR(reported_time(r.err), t_inf, 1e-4) << r.err;
}

/// An event function that is not a number from the start.
class NanEvent : public BouncingBall {
 public:
  void event_functions(double, const double*, const double*, double* g) override { g[0] = std::nan(""); }
};

TEST(Events, AnEventFunctionThatIsNotFiniteAtTheStartStopsTheRunBeforeItBegins) {
  NanEvent model;
  RunResult r = run(model, {"--solver", "cvode"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(Contains(r.err, "error: an event function (the argument of a step) is not finite at the start"));
  EXPECT_EQ(parse_csv(r.csv).rows.size(), 0u);  // nothing integrated, no row written
}

}  // namespace
}  // namespace mbgrt::test
