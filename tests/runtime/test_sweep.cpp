// Parameter sweeps (--sweep, --sweep-file, --jobs, --case-dir) and the
// progress line, on the hand-written Decay model: x = x0 exp(-k t).
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness.hpp"
#include "models.hpp"
#include "progress.hpp"

namespace mbgrt::test {
namespace {

/// A CSV whose cells may be text: every cell as a string.
std::vector<std::vector<std::string>> cells(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) row.push_back(cell);
    rows.push_back(std::move(row));
  }
  return rows;
}

std::size_t column(const std::vector<std::vector<std::string>>& table, const std::string& name) {
  for (std::size_t i = 0; i < table.at(0).size(); ++i)
    if (table[0][i] == name) return i;
  throw std::out_of_range("no column " + name);
}

/// The summary without its wall_s column (the one thing that differs from run to run).
std::string without_wall_time(const std::string& summary) {
  const auto table = cells(summary);
  const std::size_t wall = column(table, "wall_s");
  std::string out;
  for (const auto& row : table) {
    for (std::size_t i = 0; i < row.size(); ++i)
      if (i != wall) out += row[i] + ";";
    out += "\n";
  }
  return out;
}

std::string write_temp(const std::string& text) {
  const std::string path = temp_path("cases") + ".csv";
  std::ofstream(path) << text;
  return path;
}

TEST(Sweep, GridRunsEveryCombinationFirstAxisSlowest) {
  Decay m;
  RunResult r = run(m, {"--sweep", "k=0.5:1.5:3", "--sweep", "x0=1:2:2", "--jobs", "2", "--rtol", "1e-10", "--atol", "1e-12"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto table = cells(r.csv);
  ASSERT_EQ(table.size(), 7u) << r.csv;
  EXPECT_EQ(table[0][0], "case");
  const double k[] = {0.5, 0.5, 1.0, 1.0, 1.5, 1.5}, x0[] = {1, 2, 1, 2, 1, 2};
  for (std::size_t c = 0; c < 6; ++c) {
    const auto& row = table[c + 1];
    EXPECT_EQ(std::stoul(row[column(table, "case")]), c + 1);
    EXPECT_DOUBLE_EQ(std::stod(row[column(table, "k")]), k[c]);
    EXPECT_DOUBLE_EQ(std::stod(row[column(table, "x0")]), x0[c]);
    EXPECT_EQ(row[column(table, "status")], "ok");
    const double end = x0[c] * std::exp(-k[c] * 2.0);  // Decay runs to t = 2
    EXPECT_NEAR(std::stod(row[column(table, "x_final")]), end, 1e-8 * x0[c]);
    EXPECT_NEAR(std::stod(row[column(table, "x_min")]), end, 1e-8 * x0[c]);
    EXPECT_DOUBLE_EQ(std::stod(row[column(table, "x_max")]), x0[c]);
  }
  EXPECT_TRUE(Contains(r.err, "6 cases on 2 threads"));
}

TEST(Sweep, SummaryIsTheSameForAnyNumberOfJobs) {
  std::string first;
  for (const char* jobs : {"1", "2", "5"}) {
    Decay m;
    RunResult r = run(m, {"--sweep", "k=0.1:3:7", "--sweep", "x0=-1:1:3", "--jobs", jobs, "--solver", "dopri5"});
    ASSERT_EQ(r.status, 0) << r.err;
    if (first.empty())
      first = without_wall_time(r.csv);
    else
      EXPECT_EQ(without_wall_time(r.csv), first) << "--jobs " << jobs;
  }
}

TEST(Sweep, CaseMatchesASingleRunWithTheSameSettings) {
  const std::string dir = temp_path("cases");
  Decay m;
  RunResult sweep = run(m, {"--sweep", "k=0.25:0.75:3", "--case-dir", dir, "--set", "x0=3"});
  ASSERT_EQ(sweep.status, 0) << sweep.err;
  Decay one;
  RunResult single = run(one, {"--set", "x0=3", "--set", "k=0.5"});
  ASSERT_EQ(single.status, 0);
  EXPECT_EQ(read_file(dir + "/case_0002.csv"), single.csv);  // byte for byte
  EXPECT_TRUE(Contains(read_file(dir + "/case_0002.log"), "run summary for model 'decay'"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/case_0003.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/case_0004.csv"));
  std::filesystem::remove_all(dir);
}

TEST(Sweep, FailingCaseIsReportedAndTheOthersRun) {
  // rk4 at 0.01 s is unstable for k = 1e5: that case overflows
  const std::string path = write_temp("# k for each case\nk\n0.5\n1e5\n\n1.0\n");
  Decay m;
  RunResult r = run(m, {"--sweep-file", path, "--solver", "rk4", "--jobs", "2"});
  EXPECT_EQ(r.status, 1);
  const auto table = cells(r.csv);
  ASSERT_EQ(table.size(), 4u) << r.csv;
  const std::size_t status = column(table, "status"), message = column(table, "message");
  EXPECT_EQ(table[1][status], "ok");
  EXPECT_EQ(table[2][status], "failed");
  EXPECT_EQ(table[3][status], "ok");
  EXPECT_TRUE(Contains(table[2].at(message), "at t = "));
  EXPECT_NEAR(std::stod(table[3][column(table, "x_final")]), 2.0 * std::exp(-2.0), 1e-6);
  EXPECT_TRUE(Contains(r.err, "1 failed"));
  std::filesystem::remove(path);
}

/// Decay whose case k = 3 presses Ctrl-C (raises SIGINT, once) as it starts.
class InterruptedDecay : public Decay {
 public:
  std::unique_ptr<Model> make_new() const override { return std::make_unique<InterruptedDecay>(); }
  void initial(double t, double* y, double* yp) override {
    if (p("k") == 3 && !pressed_) pressed_ = true, std::raise(SIGINT);
    Decay::initial(t, y, yp);
  }

 private:
  bool pressed_ = false;
};

TEST(Sweep, CtrlCKeepsTheFinishedCasesAndSaysWhichWereNotRun) {
  InterruptedDecay m;
  RunResult r = run(m, {"--sweep", "k=1:6:6", "--jobs", "1"});
  EXPECT_EQ(r.status, 130) << r.err;
  const auto table = cells(r.csv);
  ASSERT_EQ(table.size(), 7u) << r.csv;  // every case has its row
  const std::size_t status = column(table, "status"), message = column(table, "message");
  for (std::size_t c = 1; c <= 3; ++c) {  // the case running when Ctrl-C came finishes
    EXPECT_EQ(table[c][status], "ok") << "case " << c;
    EXPECT_NEAR(std::stod(table[c][column(table, "x_final")]), 2.0 * std::exp(-2.0 * static_cast<double>(c)), 1e-5);
  }
  for (std::size_t c = 4; c <= 6; ++c) {
    EXPECT_EQ(table[c][status], "not_run") << "case " << c;
    EXPECT_EQ(table[c][column(table, "x_final")], "") << "case " << c;
    EXPECT_TRUE(Contains(table[c].at(message), "interrupted")) << "case " << c;
  }
  EXPECT_TRUE(Contains(r.err, "sweep interrupted (Ctrl-C): 3 of 6 cases not run")) << r.err;
  // and Ctrl-C is the process's own again afterwards
  struct sigaction now {};
  sigaction(SIGINT, nullptr, &now);
  EXPECT_EQ(now.sa_handler, SIG_DFL);
}

TEST(Sweep, BadSweepsExit2WithAMessage) {
  const std::string two_values = write_temp("k,x0\n1\n");
  const std::string not_a_number = write_temp("k\n1\nfast\n");
  const std::string no_cases = write_temp("k\n");
  const std::string twice = write_temp("k,k\n1,2\n");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--sweep", "k=1:2"}, "expected NAME=FROM:TO:COUNT"},
      {{"--sweep", "k=1:2:0"}, "COUNT: '0' is not a whole number"},
      {{"--sweep", "k=1:2:1"}, "COUNT 1 takes one value"},
      {{"--sweep", "k=a:2:3"}, "is not a finite number"},
      {{"--sweep", "q=1:2:3"}, "unknown parameter 'q'; known parameters: k, x0"},
      {{"--sweep", "k=1:2:3", "--sweep", "k=1:3:3"}, "given twice"},
      {{"--sweep", "k=1:2:1000", "--sweep", "x0=1:2:1001"}, "more than the 1000000"},
      {{"--sweep", "k=1:2:3", "--sweep-file", two_values}, "use one"},
      {{"--sweep", "k=1:2:3", "--linearize-at", "1"}, "not with --linearize-at"},
      {{"--sweep", "k=1:2:3", "--event-log", "e.csv"}, "--case-dir"},
      {{"--jobs", "2"}, "--jobs applies to a sweep"},
      {{"--case-dir", "d"}, "--case-dir applies to a sweep"},
      {{"--sweep", "k=1:2:3", "--jobs", "0"}, "--jobs must be at least 1"},
      {{"--sweep-file", two_values}, ":2: 1 value, but the header names 2 parameters"},
      {{"--sweep-file", not_a_number}, ":3: k = 'fast' is not a finite number"},
      {{"--sweep-file", no_cases}, "no cases after the header"},
      {{"--sweep-file", twice}, "'k' is named twice"},
      {{"--sweep-file", "/nonexistent/cases.csv"}, "cannot open"},
  };
  for (const auto& [args, message] : cases) {
    Decay m;
    RunResult r = run(m, args);
    EXPECT_EQ(r.status, 2) << args[0] << " " << args[1];
    EXPECT_TRUE(Contains(r.err, message)) << args[0] << " " << args[1];
    EXPECT_EQ(r.csv, "") << "nothing is written before the sweep starts";
  }
  for (const std::string& p : {two_values, not_a_number, no_cases, twice}) std::filesystem::remove(p);
}

TEST(Sweep, ModelThatCannotMakeInstancesIsAnError) {
  Oscillator m;  // its make_new is Model's: nullptr
  RunResult r = run(m, {"--sweep", "omega=1:2:2"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(Contains(r.err, "cannot make new instances"));
}

TEST(Progress, NotDrawnWhenStderrIsNotATerminal) {
  Decay m;
  RunResult r = run(m, {"--t-end", "2"});
  ASSERT_EQ(r.status, 0);
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
}

TEST(Progress, TextSaysHowFarAndHowLong) {
  using detail::ProgressLine;
  EXPECT_EQ(ProgressLine::text(0.25, 3.0, "t = 2.5 s of 10 s"), "t = 2.5 s of 10 s (25 %), 9 s left");
  EXPECT_EQ(ProgressLine::text(0.5, 150.0, "sweep"), "sweep (50 %), 2 min 30 s left");
  EXPECT_EQ(ProgressLine::text(0.0, 5.0, "sweep"), "sweep (0 %)");  // no rate yet: no estimate
  EXPECT_EQ(ProgressLine::text(0.9, 0.1, "x"), "x (90 %)");         // too early to say
  EXPECT_EQ(detail::format_duration(7200 + 125), "2 h 02 min");
}

}  // namespace
}  // namespace mbgrt::test
