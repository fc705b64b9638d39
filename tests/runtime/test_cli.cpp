// The command line contract (docs/cli.md, "The simulators"): option names,
// exit status 2 for bad input with a readable message, --set and
// --list-parameters.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

TEST(Cli, HelpExitsZeroAndNamesEveryContractOption) {
  Decay m;
  RunResult r = run(m, {"--help"}, false);
  EXPECT_EQ(r.status, 0);
  for (const char* opt : {"--t-end", "--interval", "--solver", "--rtol", "--atol", "--step",
                          "--set", "--out", "--quiet", "--list-parameters", "--linearize-at"})
    EXPECT_TRUE(Contains(r.out, opt)) << opt;
}

TEST(Cli, UnknownOptionExits2) {
  Decay m;
  RunResult r = run(m, {"--frobnicate"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "mbgrt: error:"));
  EXPECT_TRUE(Contains(r.err, "--frobnicate"));
}

TEST(Cli, BadValuesExit2WithMessage) {
  const std::vector<std::vector<std::string>> cases = {
      {"--t-end", "abc"},
      {"--interval", "-1"},
      {"--interval", "0"},
      {"--rtol", "-1e-6"},
      {"--solver", "leapfrog"},
      {"--t-end", "-5"},
      {"--step", "0.01"},  // --step with an adaptive solver
      {"--solver", "rk4", "--step", "0"},
      {"--linearize-at", "-1"},
      {"--t-end", "nan"},
      {"--realtime", "0"},
      {"--realtime", "fast"},
  };
  for (const auto& args : cases) {
    Decay m;
    RunResult r = run(m, args);
    EXPECT_EQ(r.status, 2) << args[0] << " " << args[1];
    EXPECT_TRUE(Contains(r.err, "mbgrt: error:")) << args[0];
    EXPECT_TRUE(r.csv.empty()) << "no CSV may be written for a usage error: " << args[0];
  }
}

TEST(Cli, RealtimePacesTheRowsToTheWallClock) {
  // 0.4 s of simulated time at 2x real time cannot take less than 0.2 s: the
  // rows wait for their moment. (A lower bound only; no timing is asserted
  // that a busy machine could miss.)
  Decay m;
  const auto start = std::chrono::steady_clock::now();
  RunResult r = run(m, {"--t-end", "0.4", "--interval", "0.05", "--realtime", "2"});
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(parse_csv(r.csv).rows.size(), 9u);
  EXPECT_GE(wall, 0.2);
  EXPECT_TRUE(Contains(r.err, "real time    paced at 2x the wall clock:")) << r.err;
  EXPECT_TRUE(Contains(r.err, "overruns of 9 points") || Contains(r.err, "overrun of 9 points")) << r.err;
  EXPECT_TRUE(Contains(r.err, "compute per frame: median")) << r.err;
}

TEST(Cli, RealtimeReportsOverruns) {
  // a billion times faster than real time: every point after the initial one is late
  Decay m;
  RunResult r = run(m, {"--t-end", "1", "--realtime", "1e9"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "paced at 1e+09x the wall clock: 10 overruns of 11 points (latest by")) << r.err;
}

TEST(Cli, UnknownSolverIsNamedInTheMessage) {
  Decay m;
  RunResult r = run(m, {"--solver", "leapfrog"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "leapfrog"));
}

TEST(Cli, EveryIntegratorInTheRegistryIsOfferedWithWhatItCanDo) {
  // mbgrt/integrators.hpp is the one place that says what an integrator
  // can do; the command line must agree with it row by row.
  Decay help_model;
  const RunResult help = run(help_model, {"--help"}, false);
  for (const IntegratorInfo& i : kIntegrators) {
    EXPECT_TRUE(Contains(help.out, std::string(i.name) + " (" + i.method + ")")) << i.name;
    Decay ode;
    RunResult plain = run(ode, {"--solver", i.name, "--t-end", "0.1"});
    // every integrator takes an ODE, if it says which unknowns are positions where the method needs that
    EXPECT_EQ(plain.status, i.needs_layout ? 2 : 0) << i.name << ": " << plain.err;
    if (i.needs_layout) continue;
    Decay stepped;
    RunResult step = run(stepped, {"--solver", i.name, "--step", "0.001", "--t-end", "0.1"});
    EXPECT_EQ(step.status, i.adaptive ? 2 : 0) << i.name << ": " << step.err;
    Decay dense;
    RunResult linear = run(dense, {"--solver", i.name, "--linear-solver", "dense", "--t-end", "0.1"});
    EXPECT_EQ(linear.status, i.linear_solver ? 0 : 2) << i.name << ": " << linear.err;
    SmallDae dae;
    RunResult d = run(dae, {"--solver", i.name, "--t-end", "0.1"});
    EXPECT_EQ(d.status, i.takes(ModelForm::dae) ? 0 : 2) << i.name << ": " << d.err;
  }
  Decay m;
  RunResult unknown = run(m, {"--solver", "leapfrog"});
  EXPECT_TRUE(Contains(unknown.err, "(use " + integrator_names() + ")")) << unknown.err;
}

TEST(Cli, SetKnownParameterChangesTheSolution) {
  Decay m;
  RunResult r = run(m, {"--set", "k=1.5", "--set", "x0=3", "--rtol", "1e-10", "--atol", "1e-12"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_EQ(csv.rows.size(), 21u);
  for (const auto& row : csv.rows) EXPECT_NEAR(row[1], 3.0 * std::exp(-1.5 * row[0]), 1e-8);
}

TEST(Cli, RepeatedSetOfTheSameNameLastWins) {
  Decay m;
  RunResult r = run(m, {"--set", "x0=5", "--set", "x0=7", "--t-end", "0"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(parse_csv(r.csv).at(0, "x"), 7.0);
}

TEST(Cli, SetUnknownParameterExits2AndListsTheKnownOnes) {
  Decay m;
  RunResult r = run(m, {"--set", "nope=1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "unknown parameter 'nope'"));
  EXPECT_TRUE(Contains(r.err, "k, x0"));
}

TEST(Cli, MalformedSetExits2) {
  for (const char* arg : {"k", "=1", "k=", "k=abc", "k=1x", "k=inf"}) {
    Decay m;
    RunResult r = run(m, {"--set", arg});
    EXPECT_EQ(r.status, 2) << arg;
    EXPECT_TRUE(Contains(r.err, "--set")) << arg;
  }
}

TEST(Cli, ListParametersPrintsNameCommaDefault) {
  Decay m;
  RunResult r = run(m, {"--list-parameters"}, false);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "k,0.5\nx0,2\n");
}

/// Decay whose x0 the model declares in mm, as mbgc emits it: listed in mm.
class DecayInMillimetres : public Decay {
 public:
  std::vector<ParameterInfo> parameters() const override {
    auto out = Decay::parameters();
    out[1] = {"x0", 2000, "mm"};
    return out;
  }
};

TEST(Cli, ListParametersGivesADeclaredUnitAsAThirdColumn) {
  DecayInMillimetres m;
  RunResult r = run(m, {"--list-parameters"}, false);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "k,0.5\nx0,2000,mm\n");
}

/// Decay with a parameter computed from another, as mbgc emits it.
class DecayWithComputedParameter : public Decay {
 public:
  std::vector<ParameterInfo> parameters() const override {
    auto out = Decay::parameters();
    out.push_back({"tau", std::nan(""), "= 1/k"});
    out.push_back({"other", std::nan(""), ""});
    return out;
  }
};

/// Decay whose units the compiler found (declared in SI, or inferred): listed in SI.
class DecayWithSiUnits : public Decay {
 public:
  std::vector<ParameterInfo> parameters() const override {
    auto out = Decay::parameters();
    out[0].si_unit = "1/s";
    out.push_back({"tau", std::nan(""), "= 1/k", "s"});
    return out;
  }
};

TEST(Cli, ListParametersGivesAnSiUnitTheCompilerFound) {
  DecayWithSiUnits m;
  RunResult r = run(m, {"--list-parameters"}, false);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "k,0.5,1/s\nx0,2\ntau,(computed: 1/k),s\n");
}

TEST(Cli, ListParametersShowsComputedOnesByFormulaNotNan) {
  DecayWithComputedParameter m;
  RunResult r = run(m, {"--list-parameters"}, false);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "k,0.5\nx0,2\ntau,(computed: 1/k)\nother,(computed)\n");
}

TEST(Cli, DaeModelRejectsNonIdaSolvers) {
  for (const char* solver : {"rk4", "dopri5", "cvode"}) {
    SmallDae m;
    RunResult r = run(m, {"--solver", solver});
    EXPECT_EQ(r.status, 2) << solver;
    EXPECT_TRUE(Contains(r.err, "DAE")) << solver;
    EXPECT_TRUE(Contains(r.err, "--solver ida")) << solver;
  }
}

TEST(Cli, UnwritableOutputFileExits2) {
  Decay m;
  RunResult r = run(m, {"-o", "/nonexistent-dir/x.csv"}, false);
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "/nonexistent-dir/x.csv"));
}

TEST(Cli, QuietSuppressesTheSummary) {
  Decay m;
  RunResult r = run(m, {"--quiet"});
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.err, "");
}

TEST(Cli, SummaryReportsTheRun) {
  Decay m;
  RunResult r = run(m, {"--solver", "cvode"});
  ASSERT_EQ(r.status, 0);
  for (const char* item :
       {"cvode", "rtol 1e-06", "atol 1e-08", "steps", "RHS", "Jacobian evaluations", "nonlinear",
        "error tests", "21 rows", "wall time"})
    EXPECT_TRUE(Contains(r.err, item)) << item << "\n" << r.err;
}

TEST(Cli, DefaultsComeFromTheModel) {
  Decay m;
  m.settings.t_end_s = 0.5;
  m.settings.interval_s = 0.25;
  m.settings.solver = Solver::dopri5;
  RunResult r = run(m, {});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(parse_csv(r.csv).rows.size(), 3u);
  EXPECT_TRUE(Contains(r.err, "dopri5"));
}

}  // namespace
}  // namespace mbgrt::test
