// ModelStructure's dependencies (modelDescription.xml): what each output,
// state derivative and event indicator reads of the states. An importer uses
// them to colour a Jacobian or to order algebraic loops, so a dependency
// left out is wrong results in another tool. Checked against the FMU itself:
// each state is moved by a little, at the start and at a point where every
// state is off its initial value (velocities at rest hide terms that are
// quadratic in them), and every unknown that moves must list that state.
#include "fmi_driver.hpp"

namespace {

using namespace fmi_test;

/// Per unknown (by value reference), the knowns it lists.
struct Structure {
  std::map<fmi3ValueReference, std::vector<fmi3ValueReference>> dependencies;
  std::vector<fmi3ValueReference> outputs, indicators;  ///< in the order listed
  int without = 0;  ///< unknowns that list none (dependencies attribute missing)
};

Structure structure(const std::string& description) {
  Structure s;
  const std::regex unknown("<(Output|ContinuousStateDerivative|EventIndicator) valueReference=\"([0-9]+)\"( dependencies=\"([0-9 ]*)\")?");
  for (auto it = std::sregex_iterator(description.begin(), description.end(), unknown); it != std::sregex_iterator(); ++it) {
    if (!(*it)[3].matched) {
      ++s.without;
      continue;
    }
    const auto vr = static_cast<fmi3ValueReference>(std::stoul((*it)[2]));
    if ((*it)[1] == "Output") s.outputs.push_back(vr);
    if ((*it)[1] == "EventIndicator") s.indicators.push_back(vr);
    std::vector<fmi3ValueReference>& known = s.dependencies[vr];
    std::istringstream list((*it)[4].str());
    for (unsigned vr; list >> vr;) known.push_back(vr);
  }
  return s;
}

/// Every output, derivative and event indicator at the states x.
std::vector<double> unknowns_at(const Fmu& fmu, fmi3Instance i, const std::vector<double>& x,
                                const std::vector<fmi3ValueReference>& outputs, std::size_t indicators) {
  auto set_states = fmu.function<decltype(fmi3SetContinuousStates)>("fmi3SetContinuousStates");
  auto derivatives = fmu.function<decltype(fmi3GetContinuousStateDerivatives)>("fmi3GetContinuousStateDerivatives");
  auto get = fmu.function<decltype(fmi3GetFloat64)>("fmi3GetFloat64");
  auto events = fmu.function<decltype(fmi3GetEventIndicators)>("fmi3GetEventIndicators");
  std::vector<double> out(outputs.size() + x.size() + indicators);
  EXPECT_EQ(set_states(i, x.data(), x.size()), fmi3OK);
  EXPECT_EQ(get(i, outputs.data(), outputs.size(), out.data(), outputs.size()), fmi3OK);
  EXPECT_EQ(derivatives(i, out.data() + outputs.size(), x.size()), fmi3OK);
  if (indicators > 0) {
    EXPECT_EQ(events(i, out.data() + outputs.size() + x.size(), indicators), fmi3OK);
  }
  return out;
}

class ModelStructure : public ::testing::TestWithParam<const char*> {};

TEST_P(ModelStructure, EveryStateAnUnknownMovesWithIsListed) {
  Fmu fmu(GetParam());
  ASSERT_TRUE(fmu.loaded());
  const Structure listed = structure(fmu.description());
  EXPECT_EQ(listed.without, 0) << "unknowns without their dependencies";
  std::vector<fmi3ValueReference> states, rates;
  fmu.states(states, rates);
  const std::vector<fmi3ValueReference>& outputs = listed.outputs;
  const std::vector<fmi3ValueReference>& indicators = listed.indicators;
  const std::size_t n = states.size();
  ASSERT_EQ(listed.dependencies.size(), outputs.size() + n + indicators.size());
  // every unknown in the order unknowns_at returns them
  std::vector<fmi3ValueReference> order = outputs;
  order.insert(order.end(), rates.begin(), rates.end());
  order.insert(order.end(), indicators.begin(), indicators.end());

  Log log;
  fmi3Instance i = fmu.model_exchange(log);
  ASSERT_EQ(fmu.enter_initialization(i), fmi3OK);
  ASSERT_EQ(fmu.exit_initialization(i), fmi3OK);
  std::vector<double> start(n);
  ASSERT_EQ(fmu.function<decltype(fmi3GetContinuousStates)>("fmi3GetContinuousStates")(i, start.data(), n), fmi3OK);
  fmu.free(i);
  i = model_exchange_at(fmu, log, start);
  std::vector<double> moved = start;
  for (std::size_t j = 0; j < n; ++j) moved[j] += 0.05 * (1 + std::abs(start[j])) * std::sin(1.0 + static_cast<double>(j));

  std::size_t listed_count = 0, observed_count = 0;
  int missing = 0;
  for (const bool at_start : {true, false}) {
    const std::vector<double>& x = at_start ? start : moved;
    const std::vector<double> base = unknowns_at(fmu, i, x, outputs, indicators.size());
    for (std::size_t j = 0; j < n; ++j) {
      const double h = 1e-6 * std::max(1.0, std::abs(x[j]));
      std::vector<double> y = x;
      y[j] = x[j] + h;
      const std::vector<double> plus = unknowns_at(fmu, i, y, outputs, indicators.size());
      y[j] = x[j] - h;
      const std::vector<double> minus = unknowns_at(fmu, i, y, outputs, indicators.size());
      for (std::size_t u = 0; u < order.size(); ++u) {
        // a change above rounding's (1e-8 of the value, h being 1e-6 of the state)
        const bool moves = std::max(std::abs(plus[u] - base[u]), std::abs(minus[u] - base[u])) >
                           1e-8 * std::max(1.0, std::abs(base[u]));
        const std::vector<fmi3ValueReference>& known = listed.dependencies.at(order[u]);
        const bool is_listed = std::find(known.begin(), known.end(), states[j]) != known.end();
        if (at_start) {
          listed_count += is_listed ? 1 : 0;
          observed_count += moves ? 1 : 0;
        }
        if (moves && !is_listed && ++missing <= 10)
          ADD_FAILURE() << "unknown " << order[u] << " moves with state " << states[j]
                        << " but does not list it (dependencies of " << order[u] << ")";
      }
    }
  }
  EXPECT_EQ(missing, 0);
  std::printf("%s: %zu of %zu unknown-by-state pairs listed (%zu seen to move at the start)\n", GetParam(), listed_count,
              order.size() * n, observed_count);
  fmu.free(i);
}

INSTANTIATE_TEST_SUITE_P(Examples, ModelStructure,
                         ::testing::Values("dc_motor", "bouncing_ball", "pendulum", "rotating_beam", "crank_rocker",
                                           "two_track"));

// The DC motor is linear: what each unknown reads is known by hand.
// i = p_L / L; omega = p_J / J; dp_L/dt = V step(t) - R i - K omega;
// dp_J/dt = K i - D omega; the supply's switch at t = 0 is an event of time.
TEST(ModelStructureOfTheMotor, ListsWhatEachUnknownReadsAndNoMore) {
  Fmu fmu("dc_motor");
  ASSERT_TRUE(fmu.loaded());
  const Structure listed = structure(fmu.description());
  const fmi3ValueReference time = fmu.reference("time"), coil = fmu.reference("motor.armature_l.p"),
                           rotor = fmu.reference("rotor.p");
  using List = std::vector<fmi3ValueReference>;
  const auto sorted = [](List l) {
    std::sort(l.begin(), l.end());
    return l;
  };
  EXPECT_EQ(listed.dependencies.at(fmu.reference("current")), List{coil});
  EXPECT_EQ(listed.dependencies.at(fmu.reference("omega")), List{rotor});
  EXPECT_EQ(listed.dependencies.at(fmu.reference("der(motor.armature_l.p)")), sorted({time, coil, rotor}));
  EXPECT_EQ(listed.dependencies.at(fmu.reference("der(rotor.p)")), sorted({coil, rotor}));
  EXPECT_EQ(listed.dependencies.at(fmu.reference("events[0]")), List{time});
}

}  // namespace
