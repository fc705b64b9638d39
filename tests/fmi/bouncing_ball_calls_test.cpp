// The bouncing ball's FMU driven through the FMI 3.0 functions: events,
// contacts and the state they hold, in co-simulation and model exchange.
// Compiled twice: into mbgc_fmi_tests, which loads the FMU's shared object
// (dlopen, as importers do), and into mbgc_fmi_inprocess_tests, which is the
// FMU: its source and the runtime's FMU library linked into the test program,
// so that CI's sanitizer pass runs the FMI functions under ASan and UBSan
// (fmi_driver.hpp, MBGC_FMI_IN_PROCESS).
#include "fmi_driver.hpp"

namespace {

using namespace fmi_test;

/// The bouncing ball co-simulated to 5 s on a 1 ms grid by `solver` (the
/// solver.method Enumeration's value), `early` return allowed or not: its
/// height (`gap`) at each grid point, and how often a step returned early.
std::vector<double> bounce(const Fmu& fmu, long long solver, bool early, int& returns) {
  Log log;
  fmi3Instance i = fmu.function<decltype(fmi3InstantiateCoSimulation)>("fmi3InstantiateCoSimulation")(
      "early", fmu.token().c_str(), "", false, true, false, early, nullptr, 0, &log, log_message, nullptr);
  EXPECT_NE(i, nullptr);
  const fmi3ValueReference method = fmu.reference("solver.method");
  const fmi3Int64 value = solver;
  EXPECT_EQ(fmu.function<decltype(fmi3SetInt64)>("fmi3SetInt64")(i, &method, 1, &value, 1), fmi3OK);
  EXPECT_EQ(fmu.enter_initialization(i), fmi3OK);
  EXPECT_EQ(fmu.exit_initialization(i), fmi3OK);
  auto do_step = fmu.function<decltype(fmi3DoStep)>("fmi3DoStep");
  const fmi3ValueReference gap = fmu.reference("gap");
  std::vector<double> heights;
  returns = 0;
  double t = 0;
  for (int n = 1; n <= 5000;) {
    const double next = n * 1e-3;
    fmi3Boolean event = false, terminate = false, returned_early = false;
    double last = 0;
    EXPECT_EQ(do_step(i, t, next - t, true, &event, &terminate, &returned_early, &last), fmi3OK) << log.all();
    EXPECT_TRUE(early || !returned_early);
    if (returned_early) {  // at an event inside the step: on from there to the same point
      EXPECT_GT(last, t);
      EXPECT_LT(last, next);
      t = last;
      ++returns;
      continue;
    }
    t = next;
    ++n;
    double height = 0;
    EXPECT_EQ(fmu.get(i, gap, height), fmi3OK);
    heights.push_back(height);
  }
  fmu.free(i);
  return heights;
}

// Early return (FMI 3.0's earlyReturnAllowed): a step ends at each event
// inside it (CVODE: the ball's 35 impacts before it rests, as the native
// run's event log has them), and changes nothing else: an importer that goes
// on to the same points gets the same heights, bit for bit, as without it.
// The integrators that locate events each their own way: CVODE (BDF),
// dopri5 (ARKODE) and rk4 (fixed steps).
TEST(BouncingBallCalls, AStepReturnsEarlyAtEachEventAndChangesNothingElse) {
  Fmu fmu("bouncing_ball");
  ASSERT_TRUE(fmu.loaded());
  for (const auto& [solver, name] : {std::pair{9LL, "cvode"}, std::pair{5LL, "dopri5"}, std::pair{4LL, "rk4"}}) {
    int without = 0, with = 0;
    const std::vector<double> plain = bounce(fmu, solver, false, without);
    const std::vector<double> early = bounce(fmu, solver, true, with);
    EXPECT_EQ(without, 0) << name;
    if (solver == 9) {
      EXPECT_EQ(with, 35);
    }
    EXPECT_GE(with, 30) << name;
    EXPECT_EQ(plain, early) << name;
  }
}

TEST(BouncingBallCalls, AMasterRollsBackToAStateAndAnotherInstanceGoesOnFromItsBytes) {
  Fmu fmu("bouncing_ball");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.started_co_simulation(log);
  ASSERT_NE(i, nullptr);
  auto get_state = fmu.function<decltype(fmi3GetFMUState)>("fmi3GetFMUState");
  auto set_state = fmu.function<decltype(fmi3SetFMUState)>("fmi3SetFMUState");
  auto free_state = fmu.function<decltype(fmi3FreeFMUState)>("fmi3FreeFMUState");
  auto size_of = fmu.function<decltype(fmi3SerializedFMUStateSize)>("fmi3SerializedFMUStateSize");
  auto serialize = fmu.function<decltype(fmi3SerializeFMUState)>("fmi3SerializeFMUState");
  auto deserialize = fmu.function<decltype(fmi3DeserializeFMUState)>("fmi3DeserializeFMUState");
  const fmi3ValueReference gap = fmu.reference("gap"), vz = fmu.reference("vz");
  for (int k = 0; k < 30; ++k) ASSERT_EQ(fmu.step(i, k * 0.01, 0.01), fmi3OK);  // to 0.3 s
  fmi3FMUState saved = nullptr;
  ASSERT_EQ(get_state(i, &saved), fmi3OK);
  ASSERT_NE(saved, nullptr);
  // on through the first impact (about 0.45 s) to 1 s, three times from the state
  auto on_to_one_second = [&](fmi3Instance at, double* values) {
    for (int k = 30; k < 100; ++k) ASSERT_EQ(fmu.step(at, k * 0.01, 0.01), fmi3OK);
    ASSERT_EQ(fmu.get(at, gap, values[0]), fmi3OK);
    ASSERT_EQ(fmu.get(at, vz, values[1]), fmi3OK);
  };
  double first[2], second[2], third[2];
  on_to_one_second(i, first);
  ASSERT_EQ(set_state(i, saved), fmi3OK);
  on_to_one_second(i, second);
  ASSERT_EQ(set_state(i, saved), fmi3OK);
  on_to_one_second(i, third);
  EXPECT_EQ(second[0], third[0]);  // from one state, the same steps: the same values
  EXPECT_EQ(second[1], third[1]);
  EXPECT_NEAR(first[1], second[1], 1e-6);  // the integrator's history is not in the state: to its tolerance
  EXPECT_GT(second[0], 0.0);  // it bounced, not fell through the floor (the contact's mode came back with the state)
  // the state's bytes, read by another instance, go on the same way
  std::size_t size = 0;
  ASSERT_EQ(size_of(i, saved, &size), fmi3OK);
  std::vector<fmi3Byte> bytes(size);
  ASSERT_EQ(serialize(i, saved, bytes.data(), size), fmi3OK);
  Log other_log;
  fmi3Instance other = fmu.co_simulation(other_log, fmu.token());
  ASSERT_NE(other, nullptr);
  fmi3FMUState read = nullptr;
  ASSERT_EQ(deserialize(other, bytes.data(), size, &read), fmi3OK);
  ASSERT_EQ(set_state(other, read), fmi3OK);
  double fourth[2];
  on_to_one_second(other, fourth);
  EXPECT_EQ(fourth[0], second[0]);
  EXPECT_EQ(fourth[1], second[1]);
  // what is not a state of this instance is refused, never dereferenced
  EXPECT_EQ(set_state(other, saved), fmi3Error);  // the first instance's
  EXPECT_TRUE(other_log.mentions("not a state this instance made")) << other_log.all();
  const std::vector<fmi3Byte> garbage(64, 7);
  fmi3FMUState none = nullptr;
  EXPECT_EQ(deserialize(other, garbage.data(), garbage.size(), &none), fmi3Error);
  EXPECT_TRUE(other_log.mentions("not an mbgc FMU's state")) << other_log.all();
  EXPECT_EQ(deserialize(other, bytes.data(), size / 2, &none), fmi3Error);
  EXPECT_EQ(free_state(i, &saved), fmi3OK);
  EXPECT_EQ(saved, nullptr);
  EXPECT_EQ(free_state(other, &read), fmi3OK);
  fmu.free(i);
  fmu.free(other);
}

// Model exchange as an importer with explicit Euler does it: the event
// indicator watched after each step, Event Mode where it changes sign, the
// impact handled there (the states jump), 1.5 s through the first two impacts.
TEST(BouncingBallCalls, ModelExchangeHandlesEachImpactAtAnEvent) {
  Fmu fmu("bouncing_ball");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.model_exchange(log);
  ASSERT_NE(i, nullptr);
  ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
  ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  auto update = fmu.function<decltype(fmi3UpdateDiscreteStates)>("fmi3UpdateDiscreteStates");
  auto enter_event = fmu.function<decltype(fmi3EnterEventMode)>("fmi3EnterEventMode");
  auto enter_continuous = fmu.function<decltype(fmi3EnterContinuousTimeMode)>("fmi3EnterContinuousTimeMode");
  auto set_time = fmu.function<decltype(fmi3SetTime)>("fmi3SetTime");
  auto get_states = fmu.function<decltype(fmi3GetContinuousStates)>("fmi3GetContinuousStates");
  auto set_states = fmu.function<decltype(fmi3SetContinuousStates)>("fmi3SetContinuousStates");
  auto derivatives = fmu.function<decltype(fmi3GetContinuousStateDerivatives)>("fmi3GetContinuousStateDerivatives");
  auto indicators = fmu.function<decltype(fmi3GetEventIndicators)>("fmi3GetEventIndicators");
  auto completed = fmu.function<decltype(fmi3CompletedIntegratorStep)>("fmi3CompletedIntegratorStep");
  auto number_of = fmu.function<decltype(fmi3GetNumberOfContinuousStates)>("fmi3GetNumberOfContinuousStates");
  const auto handle_event = [&] {
    fmi3Boolean again = true, terminate = false, nominals = false, values = false, next_defined = false;
    double next = 0;
    while (again) ASSERT_EQ(update(i, &again, &terminate, &nominals, &values, &next_defined, &next), fmi3OK);
    ASSERT_FALSE(terminate);
  };
  handle_event();
  ASSERT_EQ(enter_continuous(i), fmi3OK);
  std::size_t n = 0;
  ASSERT_EQ(number_of(i, &n), fmi3OK);
  std::vector<double> x(n), dx(n);
  double g_before = 0, g_after = 0, lowest = HUGE_VAL;
  ASSERT_EQ(indicators(i, &g_before, 1), fmi3OK);
  int impacts = 0;
  const double h = 1e-4;
  const fmi3ValueReference gap = fmu.reference("gap");
  for (int k = 1; k <= 15000; ++k) {
    ASSERT_EQ(get_states(i, x.data(), n), fmi3OK);
    ASSERT_EQ(derivatives(i, dx.data(), n), fmi3OK);
    for (std::size_t j = 0; j < n; ++j) x[j] += h * dx[j];
    ASSERT_EQ(set_time(i, k * h), fmi3OK);
    ASSERT_EQ(set_states(i, x.data(), n), fmi3OK);
    fmi3Boolean enter = false, terminate = false;
    ASSERT_EQ(completed(i, true, &enter, &terminate), fmi3OK) << log.all();
    ASSERT_EQ(indicators(i, &g_after, 1), fmi3OK);
    if ((g_before >= 0) != (g_after >= 0)) {
      ASSERT_EQ(enter_event(i), fmi3OK);
      handle_event();
      ASSERT_EQ(enter_continuous(i), fmi3OK);
      ASSERT_EQ(indicators(i, &g_after, 1), fmi3OK);
      ++impacts;
    }
    g_before = g_after;
    double height = 0;
    ASSERT_EQ(fmu.get(i, gap, height), fmi3OK);
    lowest = std::min(lowest, height);
  }
  EXPECT_EQ(impacts, 2);  // at about 0.45 s and 1.17 s (the native event log: 0.4515, 1.1740)
  EXPECT_GT(lowest, -1e-3);  // it bounced, never fell through the floor
  fmu.free(i);
}

}  // namespace
