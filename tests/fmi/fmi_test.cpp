// The examples' FMUs (mbgc --fmu, FMI 3.0 and 2.0) under an independent importer, fmusim:
// co-simulation runs the same integrator with the same steps as the
// example's own simulator and must agree with it to 1e-9 of each output's
// size; model exchange is integrated by fmusim's CVODE and must agree within
// what its tolerance reaches (stated per model below).
#include "fmi_support.hpp"

namespace {

using namespace fmi_test;

struct Example {
  const char* name;
  const char* simulator;
  double me_tolerance;  ///< fmusim --tolerance (its CVODE's relative tolerance)
  double me_bound;      ///< what model exchange must agree to, as a fraction of each output's scale
};

// Model exchange: the bounds are what CVODE at that tolerance reaches
// against the native run (at 1e-10, 1e-8), with a margin of about 10: the
// bouncing ball's impacts, located by two root finders, differ most.
const Example kExamples[] = {
    {"dc_motor", SIM_DC_MOTOR, 1e-10, 1e-8},
    {"bouncing_ball", SIM_BOUNCING_BALL, 1e-10, 1e-4},
    {"pendulum", SIM_PENDULUM, 1e-10, 1e-4},
    {"rotating_beam", SIM_ROTATING_BEAM, 1e-8, 3e-5},
    {"crank_rocker", SIM_CRANK_ROCKER, 1e-8, 1e-5},
    {"two_track", SIM_TWO_TRACK, 1e-8, 3e-5},
};

/// An example's FMU for one FMI version.
struct Case {
  Example example;
  int version;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.example.name << " FMI " << c.version; }

std::vector<Case> cases() {
  std::vector<Case> all;
  for (int version : {3, 2})
    for (const Example& e : kExamples) all.push_back({e, version});
  return all;
}

class Fmi : public ::testing::TestWithParam<Case> {
 protected:
  const Example& e = GetParam().example;
  const int version = GetParam().version;
  std::string tag(const char* kind) const { return std::string(e.name) + ".fmi" + std::to_string(version) + "." + kind; }
};

// (every file a test writes is its own: ctest runs the tests side by side)
TEST_P(Fmi, CoSimulationAgreesWithTheNativeRunTo1e9) {
  const Table reference = native(e.simulator, tag("cs.native"));
  const Table cs = imported(fmu_of(e.name, version), tag("cs"), "--interface-type cs");
  ASSERT_FALSE(reference.rows.empty());
  ASSERT_EQ(cs.rows.size(), reference.rows.size());
  std::string where;
  const double worst = worst_difference(reference, cs, where);
  std::printf("%s FMI %d co-simulation: %.2g of scale (%s)\n", e.name, version, worst, where.c_str());
  EXPECT_LE(worst, 1e-9) << where;
}

TEST_P(Fmi, ModelExchangeAgreesWithinItsTolerancesReach) {
  const Table reference = native(e.simulator, tag("me.native"));
  const Table me = imported(fmu_of(e.name, version), tag("me"),
                            "--interface-type me --solver cvode --tolerance " + number(e.me_tolerance));
  ASSERT_FALSE(reference.rows.empty());
  ASSERT_FALSE(me.rows.empty());
  std::string where;
  const double worst = worst_difference(reference, me, where, false);
  std::printf("%s FMI %d model exchange: %.2g of scale (%s)\n", e.name, version, worst, where.c_str());
  EXPECT_LE(worst, e.me_bound) << where;
}

INSTANTIATE_TEST_SUITE_P(Examples, Fmi, ::testing::ValuesIn(cases()), [](const ::testing::TestParamInfo<Case>& info) {
  return std::string(info.param.example.name) + "_fmi" + std::to_string(info.param.version);
});

TEST(FmiParameters, AStartValueChangesTheResultAsSetDoes) {
  const Table set = native(SIM_DC_MOTOR, "parameters.30V", "--set V_supply=30");
  const Table plain = native(SIM_DC_MOTOR, "parameters.60V");
  ASSERT_FALSE(set.rows.empty());
  for (int version : {3, 2}) {
    const Table start = imported(fmu_of("dc_motor", version), "parameters.30V.fmi" + std::to_string(version),
                                 "--interface-type cs --start-value V_supply 30");
    ASSERT_EQ(start.rows.size(), set.rows.size());
    std::string where;
    EXPECT_LE(worst_difference(set, start, where), 1e-9) << "FMI " << version << ": " << where;
    // and it did change it: the final current at 30 V is half that at 60 V
    EXPECT_NEAR(start.rows.back()[1], 0.5 * plain.rows.back()[1], 1e-6 * plain.rows.back()[1]);
  }
}

// A parameter computed from others (the pendulum's bob mass = m) is a
// calculated parameter: read, never set, and it follows what it is computed from.
TEST(FmiParameters, AComputedParameterFollowsWhatItIsComputedFrom) {
  for (int version : {3, 2}) {
    const std::string tag = "calculated.fmi" + std::to_string(version);
    const Table t = imported(fmu_of("pendulum", version), tag,
                             "--interface-type cs --start-value m 2.5 --output-variable bob.mass "
                             "--output-variable link.length");
    ASSERT_FALSE(t.rows.empty());
    ASSERT_EQ(t.header.size(), 3u);
    EXPECT_EQ(t.rows.front()[1], 2.5) << "FMI " << version;
    EXPECT_EQ(t.rows.back()[1], 2.5) << "FMI " << version;
    EXPECT_EQ(t.rows.back()[2], 1.0) << "FMI " << version;  // L's start value
  }
}

// Co-simulation with early return allowed (fmusim --early-return-allowed):
// a step ends at the first event inside it, and fmusim records a row there
// before it goes on. Every event of the native run (its event log) has a row
// of the FMU's at its time. fmusim takes an event within 1e-5 s of a grid
// point for that point and goes on from the event, so the integrator's first
// step after the restart aims at the next point instead: the paths part at
// the tolerance's level, which the ball's last bounces before it comes to
// rest magnify (measured: event times 1.4e-8 s, rows 2.8e-8 of scale apart).
// fmi_calls_test.cpp checks the steps bit for bit where the importer goes on
// to the same point.
TEST(FmiCoSimulation, AStepReturnsEarlyAtEachEventWhereTheImporterAllowsIt) {
  const Table reference = native(SIM_BOUNCING_BALL, "early", "--event-log '" + work("early.events.csv") + "'");
  const Table events = read_table(work("early.events.csv"));
  const Table cs = imported(fmu_of("bouncing_ball", 3), "early.cs", "--interface-type cs --early-return-allowed");
  ASSERT_GE(reference.rows.size(), 2u);
  ASSERT_FALSE(events.rows.empty());
  ASSERT_FALSE(cs.rows.empty());
  const double interval = reference.rows[1][0] - reference.rows[0][0];
  std::size_t off_grid = 0;
  for (const auto& row : cs.rows) {
    const double k = std::round(row[0] / interval);
    off_grid += std::abs(row[0] - k * interval) > 1e-9 * std::max(1.0, row[0]) ? 1 : 0;
  }
  std::size_t inside = 0;
  double worst_time = 0;
  for (const auto& event : events.rows) {
    if (event[0] >= reference.rows.back()[0]) continue;
    ++inside;
    double nearest = HUGE_VAL;
    for (const auto& row : cs.rows) nearest = std::min(nearest, std::abs(row[0] - event[0]));
    worst_time = std::max(worst_time, nearest);
  }
  EXPECT_LE(worst_time, 1e-6) << "an event of the native run without a row of the FMU's at its time";
  EXPECT_GE(off_grid, inside * 9 / 10) << "the steps did not return at the events";
  std::string where;
  const double worst = worst_difference(reference, cs, where, false);
  std::printf("bouncing_ball with early return: %zu rows off the grid for %zu events (times to %.2g s), rows %.2g of "
              "scale (%s)\n",
              off_grid, inside, worst_time, worst, where.c_str());
  EXPECT_LE(worst, 1e-6) << where;
}

// A parameter the compiler used up (the rotating beam's mode count, whether
// it has geometric stiffness) is a constant of the FMU: the run never reads
// it, so the simulator's --set of it changes no bit of the result, while a
// run-time parameter's does. Every constant of every example's FMU is tried.
TEST(FmiParameters, ACompileTimeParameterIsAConstantTheRunNeverReads) {
  int constants = 0;
  for (const Example& e : kExamples) {
    const std::string dir = work(std::string("constants.") + e.name);
    ASSERT_EQ(shell("rm -rf '" + dir + "' && mkdir -p '" + dir + "' && cd '" + dir + "' && unzip -q '" +
                    fmu_of(e.name, 3) + "' modelDescription.xml"),
              0);
    const std::string text = slurp(dir + "/modelDescription.xml");
    const std::regex constant("name=\"([^\"]+)\"[^>]*causality=\"local\" variability=\"constant\" start=\"([^\"]+)\"");
    const std::string reference = std::string("constants.") + e.name;
    bool ran = false;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), constant); it != std::sregex_iterator(); ++it) {
      const std::string name = (*it)[1], tag = reference + "." + name;
      if (!ran) native(e.simulator, reference);
      ran = true;
      ++constants;
      native(e.simulator, tag, "--set " + name + "=" + number(2 * std::stod((*it)[2]) + 1));
      EXPECT_EQ(slurp(work(tag + ".native.csv")), slurp(work(reference + ".native.csv")))
          << e.name << ": --set " << name << " changed the run";
    }
  }
  std::printf("%d constants among the examples' FMUs\n", constants);
  EXPECT_GE(constants, 2);  // the rotating beam's `modes` and `geometric`
  // a run-time parameter does change it (the comparison can fail)
  native(SIM_ROTATING_BEAM, "constants.Omega_s", "--set Omega_s=3");
  EXPECT_NE(slurp(work("constants.Omega_s.native.csv")), slurp(work("constants.rotating_beam.native.csv")));
}

// fmusim saves the FMU state at the end of a run and starts another from it:
// the second half of a run, continued from the state at its middle, against
// the uninterrupted run (the ball bounces on in between: the contact's modes
// are in the state). The importer's integrator (model exchange) and the
// FMU's (co-simulation) start again there, so the two agree to what their
// tolerance reaches (measured 6.6e-9 m and 1.9e-8 m at rtol 1e-10).
TEST(FmiState, ARunContinuedFromASavedStateAgreesWithTheUninterruptedRun) {
  // the ball in flight between bounces, the ball at rest on the floor (its
  // contact closed), the motor on its supply (the step's mode on)
  const struct {
    const char* example;
    double split, stop;
  } kRuns[] = {{"bouncing_ball", 1.5, 3.0}, {"bouncing_ball", 4.5, 5.0}, {"dc_motor", 1.0, 2.0}};
  for (const auto& run : kRuns)
    for (int version : {3, 2})
      for (const char* kind : {"cs", "me"}) {
        const std::string base = std::string("--interface-type ") + kind +
                                 (std::string(kind) == "me" ? " --solver cvode --tolerance 1e-10" : "");
        const std::string tag = std::string(run.example) + ".state" + number(run.split) + ".fmi" +
                                std::to_string(version) + "." + kind;
        const std::string state = work(tag + ".bin"), fmu = fmu_of(run.example, version);
        std::remove(state.c_str());
        const Table whole = imported(fmu, tag + ".whole", base + " --stop-time " + number(run.stop));
        imported(fmu, tag + ".first",
                 base + " --stop-time " + number(run.split) + " --final-fmu-state-file \"" + state + "\"");
        const Table second = imported(fmu, tag + ".second",
                                      base + " --start-time " + number(run.split) + " --stop-time " + number(run.stop) +
                                          " --initial-fmu-state-file \"" + state + "\"");
        ASSERT_FALSE(whole.rows.empty());
        ASSERT_FALSE(second.rows.empty());
        EXPECT_EQ(second.rows.front()[0], run.split);
        EXPECT_EQ(second.rows.back()[0], run.stop);
        // the uninterrupted run from the split on, at its output grid (not
        // the rows fmusim adds before and after each event, at its time)
        Table later = whole;
        std::map<double, int> at;
        for (const auto& r : whole.rows) ++at[r[0]];
        later.rows.erase(std::remove_if(later.rows.begin(), later.rows.end(),
                                        [&](const auto& r) { return r[0] < run.split - 1e-9 || at[r[0]] > 1; }),
                         later.rows.end());
        std::string where;
        const double worst = worst_difference(later, second, where, false);
        std::printf("%s FMI %d %s continued from its state at %g s: %.2g of scale (%s)\n", run.example, version, kind,
                    run.split, worst, where.c_str());
        EXPECT_LE(worst, 1e-6) << tag << ": " << where;
      }
}

TEST(FmiBinary, TheSharedObjectLoadsOnlyTheCAndCxxRuntimeAndLibm) {
  const std::string dir = work("dc_motor_unzipped");
  ASSERT_EQ(shell("rm -rf \"" + dir + "\" && mkdir -p \"" + dir + "\" && cd \"" + dir + "\" && unzip -q \"" +
                  fmu_of("dc_motor", 3) + "\""),
            0);
  const std::string libs = work("dc_motor_ldd.txt");
  ASSERT_EQ(shell("ldd \"" + dir + "/binaries/x86_64-linux/dc_motor.so\" > \"" + libs + "\""), 0);
  std::istringstream lines(slurp(libs));
  int count = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string name;
    words >> name;
    const bool allowed = name.rfind("linux-vdso", 0) == 0 || name.rfind("libstdc++.so", 0) == 0 ||
                         name.rfind("libm.so", 0) == 0 || name.rfind("libgcc_s.so", 0) == 0 ||
                         name.rfind("libc.so", 0) == 0 || name.find("ld-linux") != std::string::npos;
    EXPECT_TRUE(allowed) << "the FMU loads " << name;
    ++count;
  }
  EXPECT_GE(count, 3);
  // the FMI functions (3.0's and 2.0's) are what it exports, the runtime and SUNDIALS stay inside
  const std::string symbols = work("dc_motor_symbols.txt");
  ASSERT_EQ(shell("nm -D --defined-only \"" + dir + "/binaries/x86_64-linux/dc_motor.so\" > \"" + symbols + "\""), 0);
  std::istringstream defined(slurp(symbols));
  int fmi3 = 0, fmi2 = 0;
  for (std::string line; std::getline(defined, line);) {
    const std::string name = line.substr(line.rfind(' ') + 1);
    fmi3 += name.rfind("fmi3", 0) == 0 ? 1 : 0;
    fmi2 += name.rfind("fmi2", 0) == 0 ? 1 : 0;
    EXPECT_TRUE(name.rfind("fmi3", 0) == 0 || name.rfind("fmi2", 0) == 0) << "the FMU exports " << name;
  }
  EXPECT_EQ(fmi3, 75);  // every function of FMI 3.0
  EXPECT_EQ(fmi2, 44);  // and of FMI 2.0
}

}  // namespace
