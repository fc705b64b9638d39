// An importer of our own that calls an FMU's FMI 3.0 functions directly
// (dlopen, as importers do), for what fmusim never does: calls out of the
// state machine's order, unknown value references, NaN, a fixed parameter
// set after initialisation, a wrong token, two instances in one process, and
// a model that stops at the extremes. Each bad call must return fmi3Error
// with the reason logged, never crash or hand back a NaN.
#include "fmi_driver.hpp"

namespace {

using namespace fmi_test;

TEST(FmiCalls, ATokenNotTheFmusIsRefusedAndSaidWhy) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  EXPECT_EQ(fmu.co_simulation(log, "{not-this-one}"), nullptr);
  EXPECT_TRUE(log.mentions("is not this FMU's")) << log.all();
}

TEST(FmiCalls, AnUnknownValueReferenceIsAnError) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.co_simulation(log, fmu.token());
  ASSERT_NE(i, nullptr);
  double v = 0;
  EXPECT_EQ(fmu.get(i, 100000, v), fmi3Error);
  EXPECT_TRUE(log.mentions("unknown value reference 100000")) << log.all();
  EXPECT_EQ(fmu.set(i, 100000, 1.0), fmi3Error);
  fmu.free(i);
}

TEST(FmiCalls, ANanOrAnOutputSetIsAnError) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.co_simulation(log, fmu.token());
  ASSERT_NE(i, nullptr);
  EXPECT_EQ(fmu.set(i, fmu.reference("V_supply"), NAN), fmi3Error);
  EXPECT_TRUE(log.mentions("'V_supply' (value reference")) << log.all();
  EXPECT_TRUE(log.mentions("cannot be set to nan")) << log.all();
  EXPECT_EQ(fmu.set(i, fmu.reference("omega"), 1.0), fmi3Error);
  EXPECT_TRUE(log.mentions("is an output: only parameters and solver settings can be set")) << log.all();
  fmu.free(i);
}

TEST(FmiCalls, ACompileTimeParameterIsReadButNeverSet) {
  Fmu fmu("rotating_beam");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.co_simulation(log, fmu.token());
  ASSERT_NE(i, nullptr);
  double modes = 0;
  EXPECT_EQ(fmu.get(i, fmu.reference("modes"), modes), fmi3OK);
  EXPECT_EQ(modes, 3.0);
  EXPECT_EQ(fmu.set(i, fmu.reference("modes"), 4.0), fmi3Error);
  EXPECT_TRUE(log.mentions("is a compile-time parameter (fixed when mbgc compiled the model")) << log.all();
  fmu.free(i);
}

TEST(FmiCalls, AComputedParameterIsReadOnceInitialisedButNeverSet) {
  Fmu fmu("pendulum");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.co_simulation(log, fmu.token());
  ASSERT_NE(i, nullptr);
  EXPECT_EQ(fmu.set(i, fmu.reference("bob.mass"), 3.0), fmi3Error);
  EXPECT_TRUE(log.mentions("is a parameter computed from others (set those)")) << log.all();
  ASSERT_EQ(fmu.set(i, fmu.reference("m"), 2.5), fmi3OK);
  ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
  ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  double mass = 0;
  EXPECT_EQ(fmu.get(i, fmu.reference("bob.mass"), mass), fmi3OK);
  EXPECT_EQ(mass, 2.5);
  fmu.free(i);
}

TEST(FmiCalls, AFixedParameterSetAfterInitialisationIsAnError) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.co_simulation(log, fmu.token());
  ASSERT_NE(i, nullptr);
  EXPECT_EQ(fmu.set(i, fmu.reference("V_supply"), 30.0), fmi3OK);  // before: as --set
  ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
  ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  EXPECT_EQ(fmu.set(i, fmu.reference("V_supply"), 40.0), fmi3Error);
  EXPECT_TRUE(log.mentions("'V_supply' (value reference")) << log.all();
  EXPECT_TRUE(log.mentions("is fixed: it can be set only before ExitInitializationMode")) << log.all();
  double v = 0;
  EXPECT_EQ(fmu.get(i, fmu.reference("V_supply"), v), fmi3OK);
  EXPECT_EQ(v, 30.0);
  fmu.free(i);
}

TEST(FmiCalls, CallsOutOfTheStateMachinesOrderAreErrors) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.co_simulation(log, fmu.token());
  ASSERT_NE(i, nullptr);
  EXPECT_EQ(fmu.step(i, 0.0, 0.01), fmi3Error);
  EXPECT_TRUE(log.mentions("DoStep is not allowed in Instantiated")) << log.all();
  EXPECT_EQ(fmu.exit_initialization(i), fmi3Error);
  EXPECT_TRUE(log.mentions("ExitInitializationMode is not allowed in Instantiated")) << log.all();
  double omega = 0;
  EXPECT_EQ(fmu.get(i, fmu.reference("omega"), omega), fmi3Error);
  EXPECT_TRUE(log.mentions("it has a value once the initialisation is done")) << log.all();
  ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
  ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  EXPECT_EQ(fmu.step(i, 0.5, 0.01), fmi3Error);  // not where the FMU is
  EXPECT_TRUE(log.mentions("DoStep from t = 0.5 s, but the FMU is at t = 0 s")) << log.all();
  EXPECT_EQ(fmu.step(i, 0.0, -0.01), fmi3Error);
  EXPECT_EQ(fmu.step(i, 0.0, 0.01), fmi3OK);  // the refused calls changed nothing
  fmi3Boolean event = false, terminate = false;
  EXPECT_EQ(fmu.function<decltype(fmi3CompletedIntegratorStep)>("fmi3CompletedIntegratorStep")(i, true, &event, &terminate),
            fmi3Error);  // model exchange's, on a co-simulation instance in Step Mode
  fmu.free(i);
  // model exchange: derivatives before the initialisation
  Log me_log;
  fmi3Instance m = fmu.model_exchange(me_log);
  ASSERT_NE(m, nullptr);
  double dx[2];
  EXPECT_EQ(fmu.function<decltype(fmi3GetContinuousStateDerivatives)>("fmi3GetContinuousStateDerivatives")(m, dx, 2),
            fmi3Error);
  EXPECT_TRUE(me_log.mentions("GetContinuousStateDerivatives is not allowed in Instantiated")) << me_log.all();
  fmu.free(m);
}

TEST(FmiCalls, TwoInstancesInOneProcessRunApart) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log_a, log_b;
  fmi3Instance a = fmu.co_simulation(log_a, fmu.token()), b = fmu.co_simulation(log_b, fmu.token());
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  ASSERT_EQ(fmu.set(b, fmu.reference("V_supply"), 30.0), fmi3OK);
  for (fmi3Instance i : {a, b}) {
    ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
    ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  }
  for (int k = 0; k < 200; ++k)  // stepped in turns
    for (fmi3Instance i : {a, b}) ASSERT_EQ(fmu.step(i, k * 0.01, 0.01), fmi3OK);
  double current_a = 0, current_b = 0;
  ASSERT_EQ(fmu.get(a, fmu.reference("current"), current_a), fmi3OK);
  ASSERT_EQ(fmu.get(b, fmu.reference("current"), current_b), fmi3OK);
  EXPECT_NEAR(current_a, 24.7659, 1e-4);  // the simulator's final current (README)
  EXPECT_NEAR(current_b, 0.5 * current_a, 1e-9 * current_a);  // linear in the supply
  fmu.free(a);
  fmu.free(b);
}

TEST(FmiCalls, DirectionalDerivativesAreTheModelsJacobian) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = model_exchange_at(fmu, log, {0.3, 0.7});
  auto directional = fmu.function<decltype(fmi3GetDirectionalDerivative)>("fmi3GetDirectionalDerivative");
  const fmi3ValueReference unknowns[] = {fmu.reference("der(motor.armature_l.p)"), fmu.reference("der(rotor.p)"),
                                         fmu.reference("current")};
  const fmi3ValueReference coil = fmu.reference("motor.armature_l.p"), rotor = fmu.reference("rotor.p");
  const double one = 1.0;
  double column[3] = {0, 0, 0};
  // d/dp of the coil's flux linkage p (i = p / L): -R/L, K/L; d(current)/dp = 1/L
  const double R = 0.4, L = 0.05, K = 0.678, J = 0.57207, D = 0.226;
  ASSERT_EQ(directional(i, unknowns, 2, &coil, 1, &one, 1, column, 2), fmi3OK);
  EXPECT_NEAR(column[0], -R / L, 1e-12);
  EXPECT_NEAR(column[1], K / L, 1e-12);
  ASSERT_EQ(directional(i, &unknowns[1], 1, &rotor, 1, &one, 1, column, 1), fmi3OK);
  EXPECT_NEAR(column[0], -D / J, 1e-12);
  // with an output among the unknowns: central differences (linear here: to rounding)
  ASSERT_EQ(directional(i, unknowns, 3, &coil, 1, &one, 1, column, 3), fmi3OK);
  EXPECT_NEAR(column[0], -R / L, 1e-6);
  EXPECT_NEAR(column[2], 1 / L, 1e-6);
  // a seed along both states at once is the sum of the columns
  const fmi3ValueReference both[] = {coil, rotor};
  const double seed[] = {2.0, -3.0};
  ASSERT_EQ(directional(i, unknowns, 2, both, 2, seed, 2, column, 2), fmi3OK);
  EXPECT_NEAR(column[0], 2 * (-R / L) - 3 * (-K / J), 1e-12);
  // a parameter is not a known
  const fmi3ValueReference supply = fmu.reference("V_supply");
  EXPECT_EQ(directional(i, unknowns, 1, &supply, 1, &one, 1, column, 1), fmi3Error);
  EXPECT_TRUE(log.mentions("the knowns are continuous states")) << log.all();
  fmu.free(i);
}

class NonlinearFmi : public ::testing::TestWithParam<const char*> {};

// (two_track has no generated Jacobian, its tree being eliminated in joint
// coordinates: the FMU differences its derivatives along the seed, with a
// step of 1e-6 of the states the seed moves; one of the largest state's, a
// wheel's spin rate, made it 1.4e-4 off)
TEST_P(NonlinearFmi, DirectionalDerivativesMatchTheDerivativesDifferenced) {
  Fmu fmu(GetParam());
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.model_exchange(log);
  ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
  ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  std::size_t n = 0;
  ASSERT_EQ(fmu.function<decltype(fmi3GetNumberOfContinuousStates)>("fmi3GetNumberOfContinuousStates")(i, &n), fmi3OK);
  std::vector<double> x(n);
  ASSERT_EQ(fmu.function<decltype(fmi3GetContinuousStates)>("fmi3GetContinuousStates")(i, x.data(), n), fmi3OK);
  fmu.free(i);
  i = model_exchange_at(fmu, log, x);
  auto set_states = fmu.function<decltype(fmi3SetContinuousStates)>("fmi3SetContinuousStates");
  auto derivatives = fmu.function<decltype(fmi3GetContinuousStateDerivatives)>("fmi3GetContinuousStateDerivatives");
  auto directional = fmu.function<decltype(fmi3GetDirectionalDerivative)>("fmi3GetDirectionalDerivative");
  std::vector<fmi3ValueReference> states, rates;
  fmu.states(states, rates);
  ASSERT_EQ(states.size(), n);
  std::vector<double> plus(n), minus(n), exact(n), column_plus(n), column_minus(n);
  double worst = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double one = 1.0;
    ASSERT_EQ(directional(i, rates.data(), n, &states[j], 1, &one, 1, exact.data(), n), fmi3OK);
    const double h = 1e-6 * std::max(1.0, std::abs(x[j]));
    std::vector<double> y = x;
    y[j] = x[j] + h;
    ASSERT_EQ(set_states(i, y.data(), n), fmi3OK);
    ASSERT_EQ(derivatives(i, column_plus.data(), n), fmi3OK);
    y[j] = x[j] - h;
    ASSERT_EQ(set_states(i, y.data(), n), fmi3OK);
    ASSERT_EQ(derivatives(i, column_minus.data(), n), fmi3OK);
    ASSERT_EQ(set_states(i, x.data(), n), fmi3OK);
    for (std::size_t r = 0; r < n; ++r) {
      const double differenced = (column_plus[r] - column_minus[r]) / (2 * h);
      const double e = std::abs(differenced - exact[r]) / std::max(1.0, std::abs(exact[r]));
      worst = std::max(worst, e);
    }
  }
  EXPECT_LT(worst, 1e-5);  // central differences' truncation and rounding, not the Jacobian's
  fmu.free(i);
}

INSTANTIATE_TEST_SUITE_P(Examples, NonlinearFmi,
                         ::testing::Values("pendulum", "bouncing_ball", "rotating_beam", "crank_rocker", "two_track"));

TEST(FmiCalls, AModelThatBlowsUpStopsWithTheReportNeverANan) {
  Fmu fmu("blowup");
  ASSERT_TRUE(fmu.loaded());
  Log log;
  fmi3Instance i = fmu.started_co_simulation(log);
  ASSERT_NE(i, nullptr);
  fmi3Status status = fmi3OK;
  double t = 0;
  for (; t < 2 - 1e-9 && status == fmi3OK; t += 0.1) {
    status = fmu.step(i, t, 0.1);
    double v = 0;
    if (status == fmi3OK) {
      EXPECT_EQ(fmu.get(i, fmu.reference("v"), v), fmi3OK);
      EXPECT_TRUE(std::isfinite(v)) << "at t = " << t + 0.1;
    }
  }
  EXPECT_EQ(status, fmi3Error);
  EXPECT_LT(t, 1.05);  // the source is infinite at t = 1 s
  EXPECT_TRUE(log.mentions("cap.q")) << log.all();  // the state, in model terms
  double v = 0;
  EXPECT_EQ(fmu.get(i, fmu.reference("v"), v), fmi3Error);  // nothing after the failure
  EXPECT_TRUE(log.mentions("the FMU failed at an earlier call")) << log.all();
  fmu.free(i);
}

}  // namespace
