// events_test.cpp — the runtime's events (issue 16, point 1): each step(x)
// of a model is held as a mode between the zero crossings of x, which every
// integrator locates; the run summary lists the switches and --event-log
// writes them. models/events.mbg charges a capacitor with currents that
// switch at a time (t_off) and at two voltages (v1 rising, v2 falling), so
// its voltage is piecewise linear and known in closed form; a method that
// locates the switches integrates each piece exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim_run.hpp"

using namespace numeric;

namespace {

// The model's parameters and the times its currents switch.
constexpr double kC = 2, kI0 = 2, kI1 = 3, kI2 = 0.5, kV1 = 0.4, kV2 = 1, kTOff = 0.75;
constexpr double kT1 = kV1 * kC / (kI0 - kI2);                                      // v reaches v1 (8/15 s)
constexpr double kVOff = kV1 + (kI0 + kI1 - kI2) / kC * (kTOff - kT1);              // v at t_off
constexpr double kT2 = kTOff + (kV2 - kVOff) / ((kI1 - kI2) / kC);                  // v reaches v2

/// The voltage in closed form: the capacitor's current, piece by piece.
double voltage(double t) {
  if (t <= kT1) return (kI0 - kI2) / kC * t;
  if (t <= kTOff) return kV1 + (kI0 + kI1 - kI2) / kC * (t - kT1);
  if (t <= kT2) return kVOff + (kI1 - kI2) / kC * (t - kTOff);
  return kV2 + kI1 / kC * (t - kT2);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

class EventsBySolver : public ::testing::TestWithParam<const char*> {};

TEST_P(EventsBySolver, ThePiecewiseLinearVoltageIsExactAndTheSwitchesAreWhereTheClosedFormPutsThem) {
  const std::string solver = GetParam();
  const std::string log_path = work_file("events_" + solver, "_events.csv");
  SimRun r = run(EVENTS_SIM, "--solver " + solver + " --event-log \"" + log_path + "\"", "events_" + solver);
  ASSERT_EQ(r.status, 0) << r.log;
  ASSERT_EQ(r.csv.rows.size(), 11u);
  // rk4 and dopri5 are exact on a linear piece, BDF too (its polynomials
  // reproduce a line); what is left is where the switches were put.
  const double tol = solver == "rk4" || solver == "dopri5" ? 1e-12 : 1e-9;
  for (const auto& row : r.csv.rows) EXPECT_NEAR(row[r.csv.col("v")], voltage(row[0]), tol) << solver << " at t = " << row[0];
  // The log: three switches, in order, at the closed form's times.
  const Csv events = read_csv(log_path);
  ASSERT_EQ(events.header, (std::vector<std::string>{"t", "event", "name", "state", "jump", "note"}));
  ASSERT_EQ(events.rows.size(), 3u) << slurp(log_path);
  EXPECT_NEAR(events.rows[0][0], kT1, 1e-9);
  EXPECT_NEAR(events.rows[1][0], kTOff, 1e-12);  // a time event: t - t_off, located where it is 0
  EXPECT_NEAR(events.rows[2][0], kT2, 1e-9);
  const std::string text = slurp(log_path);
  // each named by its step, the element and the model line it is in
  EXPECT_TRUE(contains(text, ",\"heaviside(cap.e - v1), Sf src (")) << text;
  EXPECT_TRUE(contains(text, ",\"heaviside(t - t_off) (time event), Sf src (")) << text;
  EXPECT_TRUE(contains(text, ",\"heaviside(v2 - cap.e), Sf src (")) << text;
  EXPECT_TRUE(contains(text, "events.mbg:15:4)\",on,0")) << text;
  EXPECT_TRUE(contains(text, "events.mbg:15:4)\",off,0")) << text;
  // The run summary lists them in model terms.
  EXPECT_TRUE(contains(r.log, "events       3 switches of 3 events:")) << r.log;
  EXPECT_TRUE(contains(r.log, "heaviside(v2 - cap.e), Sf src (")) << r.log;
}

INSTANTIATE_TEST_SUITE_P(Solvers, EventsBySolver, ::testing::Values("rk4", "dopri5", "cvode", "ida"));

TEST(Events, LocatedSwitchesMakeRk4ExactWhereStepsStraddlingThemMissByAMillivolt) {
  // The same model integrated by the same RK4 step (0.01 s) without events,
  // in the test: each step evaluated where it stands, so the three steps
  // that straddle a switch mix the currents before and after it.
  auto rate = [](double t, double v) {
    const double i = kI0 * (t >= kTOff ? 0.0 : 1.0) + kI1 * (v - kV1 >= 0 ? 1.0 : 0.0) - kI2 * (kV2 - v >= 0 ? 1.0 : 0.0);
    return i / kC;
  };
  double t = 0, v = 0;
  const double h = 0.01;
  for (int k = 0; k < 100; ++k, t = k * h) {
    const double k1 = rate(t, v), k2 = rate(t + h / 2, v + h / 2 * k1), k3 = rate(t + h / 2, v + h / 2 * k2),
                 k4 = rate(t + h, v + h * k3);
    v += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  const double straddled = std::abs(v - voltage(1.0));
  SimRun r = run(EVENTS_SIM, "--solver rk4 --step 0.01", "events_rk4_plain");
  ASSERT_EQ(r.status, 0) << r.log;
  const double located = std::abs(r.csv.at(1.0, "v") - voltage(1.0));
  EXPECT_GT(straddled, 1e-4);
  EXPECT_LT(located, 1e-12);
  RecordProperty("rk4_error_straddled", std::to_string(straddled));
  RecordProperty("rk4_error_located", std::to_string(located));
}

TEST(Events, ATimeKinkIsAnEventTooSoRk4IntegratesARampExactly) {
  // ramp(t0) = max(0, t - t0): the kink at t0 = 0.35 s lies inside the step
  // from 0.3 to 0.4 s. As an event the step is cut there and both pieces are
  // polynomials of degree 1, whose integral RK4 gets exactly (a step across
  // the kink would carry an error of order h^2 / C).
  SimRun r = run(EVENTS_RAMP_SIM, "--event-log \"" + work_file("events_ramp", "_events.csv") + "\"", "events_ramp");
  ASSERT_EQ(r.status, 0) << r.log;
  for (const auto& row : r.csv.rows) {
    const double t = row[0], d = std::max(0.0, t - 0.35);
    EXPECT_NEAR(row[r.csv.col("v")], d * d / (2 * 2.0), 1e-14) << "at t = " << t;
  }
  const Csv events = read_csv(work_file("events_ramp", "_events.csv"));
  ASSERT_EQ(events.rows.size(), 1u);
  EXPECT_NEAR(events.rows[0][0], 0.35, 1e-14);
}

TEST(EventsTable, ATableOfTimeIsExactWithEverySolverFromItsFirstPoint) {
  // table(t, [[0, 0], [1, 2], [3, 2], [4, 0]]): a ramp up, a plateau, a ramp
  // down, then 0, integrated. Its first kink is at the start time, where the
  // argument of max(0, t - 0) is exactly 0: the runtime must take the side
  // the argument moves to (a ramp from t = 0 once stayed at 0).
  auto y = [](double t) { return t < 1 ? 2 * t : t < 3 ? 2.0 : t < 4 ? 2 * (4 - t) : 0.0; };
  auto q = [](double t) {
    return t < 1 ? t * t : t < 3 ? 1 + 2 * (t - 1) : t < 4 ? 6 - (4 - t) * (4 - t) : 6.0;
  };
  for (const char* solver : {"cvode", "dopri5", "rk4"}) {
    SimRun r = run(EVENTS_TABLE_SIM, std::string("--solver ") + solver, std::string("events_table_") + solver);
    ASSERT_EQ(r.status, 0) << r.log;
    for (const auto& row : r.csv.rows) {
      EXPECT_NEAR(row[r.csv.col("y")], y(row[0]), 1e-12) << solver << " at t = " << row[0];
      EXPECT_NEAR(row[r.csv.col("q")], q(row[0]), 1e-8) << solver << " at t = " << row[0];
    }
  }
}

}  // namespace
