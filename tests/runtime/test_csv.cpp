// CSV layout (docs/cli.md, "Output and the run summary"): `t,<outputs>`
// header, one row per communication point from t_start to t_end, numbers that
// read back exactly.
#include <gtest/gtest.h>

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "cli.hpp"
#include "csv.hpp"
#include "harness.hpp"
#include "models.hpp"

namespace mbgrt::test {
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(Csv, HeaderIsTThenOutputsInDeclarationOrder) {
  Clock m;
  RunResult r = run(m, {});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lines(r.csv).at(0), "t,a.b,third_of_t");
}

/// Clock whose first output the model declares in metres, as mbgc emits it.
class ClockWithUnits : public Clock {
 public:
  std::vector<std::string> output_units() const override { return {"m", ""}; }
};

TEST(Csv, TheHeaderNamesTheUnitAnOutputIsDeclaredIn) {
  ClockWithUnits m;
  RunResult r = run(m, {});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lines(r.csv).at(0), "t,a.b [m],third_of_t");
}

TEST(Csv, OneRowPerIntervalIncludingStartAndEnd) {
  Clock m;
  RunResult r = run(m, {});
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<std::string> l = lines(r.csv);
  ASSERT_EQ(l.size(), 12u);  // header + t = 0, 0.1, ..., 1
  // Decimal intervals produce the decimal times a reader expects, not 0.30000000000000004.
  EXPECT_EQ(l[1].substr(0, 2), "0,");
  EXPECT_EQ(l[4].substr(0, 4), "0.3,");
  EXPECT_EQ(l[11].substr(0, 2), "1,");
}

TEST(Csv, LastRowIsAtTEndWhenTheSpanIsNotAWholeNumberOfIntervals) {
  Clock m;
  RunResult r = run(m, {"--interval", "0.3"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  std::vector<double> expected{0.0, 0.3, 0.6, 0.9, 1.0};
  ASSERT_EQ(csv.rows.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_DOUBLE_EQ(csv.rows[i][0], expected[i]);
  EXPECT_EQ(csv.rows.back()[0], 1.0);
}

TEST(Csv, ZeroLengthRunWritesTheInitialRowOnly) {
  Clock m;
  RunResult r = run(m, {"--t-end", "0"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(parse_csv(r.csv).rows.size(), 1u);
}

TEST(Csv, NumbersReadBackBitForBit) {
  Clock m;
  RunResult r = run(m, {"--interval", "0.07"});
  ASSERT_EQ(r.status, 0) << r.err;
  Csv csv = parse_csv(r.csv);
  ASSERT_GT(csv.rows.size(), 10u);
  for (const auto& row : csv.rows) EXPECT_EQ(row[2], row[0] / 3.0) << "t = " << row[0];
}

TEST(Csv, WithoutOutFileTheCsvGoesToStdout) {
  Clock m;
  RunResult r = run(m, {"--t-end", "0.2"}, false);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out,
            "t,a.b,third_of_t\n0,0,0\n0.1,0.1,0.03333333333333333\n0.2,0.2,0.06666666666666667\n");
}

/// Decay that is sent `signal` (once) when the integrator first passes t = 0.55.
class SignalledDecay : public Decay {
 public:
  explicit SignalledDecay(int signal) : signal_(signal) {}
  void derivative(double t, const double* y, double* dy) override {
    if (t > 0.55 && !sent_) sent_ = true, std::raise(signal_);
    Decay::derivative(t, y, dy);
  }

 private:
  int signal_;
  bool sent_ = false;
};

TEST(Csv, ARunAskedToStopEndsAfterAWholeRowAndSaysSo) {
  for (const auto& [signal, name] : {std::pair{SIGTERM, "SIGTERM"}, {SIGINT, "SIGINT (Ctrl-C)"}, {SIGHUP, "SIGHUP"}}) {
    SignalledDecay m(signal);
    RunResult r = run(m, {"--solver", "rk4", "--quiet"});
    EXPECT_EQ(r.status, 128 + signal) << name << "\n" << r.err;
    // every row whole and the file ending with its newline: the signal came
    // inside a step, the run stopped after that step's row
    ASSERT_FALSE(r.csv.empty());
    EXPECT_EQ(r.csv.back(), '\n') << name;
    const Csv csv = parse_csv(r.csv);
    ASSERT_EQ(csv.rows.size(), 7u) << name << "\n" << r.csv;  // t = 0 to 0.6
    for (const auto& row : csv.rows) EXPECT_NEAR(row[1], m.exact(row[0]), 1e-6) << name;
    EXPECT_DOUBLE_EQ(csv.rows.back()[0], 0.6) << name;
    EXPECT_TRUE(Contains(r.err, std::string("stopped by ") + name + " at t = 0.6 s of 2 s; the 7 rows written are whole"))
        << r.err;
    // and the signal is the process's own again afterwards
    struct sigaction now {};
    sigaction(signal, nullptr, &now);
    EXPECT_EQ(now.sa_handler, SIG_DFL) << name;
  }
}

/// Runs `body` in a child process, which then dies by SIGKILL, and waits for
/// that child and for every process it left behind (its CSV writer): this
/// process is their subreaper while it waits.
void run_and_kill(const std::function<void()>& body) {
  ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    body();
    std::raise(SIGKILL);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << status;
  while (::waitpid(-1, &status, 0) > 0) EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  ::prctl(PR_SET_CHILD_SUBREAPER, 0);
}

TEST(Csv, ARowTheSimulatorWasKilledInTheMiddleOfIsNotWritten) {
  // A SIGKILL can stop write() between two pages of the file: the row then
  // ends half-way. Written through its writer process, the file keeps only
  // whole rows. As written directly, the same death leaves the torn row
  // (the second case: what the writer is for).
  const std::string path = temp_path("killed.csv");
  for (auto rows : {detail::OutputFile::Rows::Whole, detail::OutputFile::Rows::AsWritten}) {
    run_and_kill([&] {
      detail::OutputFile out(path, rows);
      out.write("t,x\n0,1\n");
      out.write("0.1,0.9");  // a row cut short: the text the kernel took before the kill
    });
    const bool whole = rows == detail::OutputFile::Rows::Whole;
    EXPECT_EQ(read_file(path), whole ? "t,x\n0,1\n" : "t,x\n0,1\n0.1,0.9") << (whole ? "whole rows" : "as written");
  }
  std::filesystem::remove(path);
}

TEST(Csv, AKilledSimulatorsFileHoldsTheRowsItFinished) {
  // The whole run through run_main: rows keep coming until the kill, and the
  // writer writes every one the simulator finished before it.
  const std::string path = temp_path("killed_run.csv");
  run_and_kill([&] {
    SignalledDecay m(SIGKILL);
    run(m, {"--solver", "rk4", "--quiet", "-o", path}, false);
  });
  const std::string text = read_file(path);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << text;
  const Csv csv = parse_csv(text);
  ASSERT_EQ(csv.rows.size(), 6u) << text;  // t = 0 to 0.5: the kill came inside the step to 0.6
  Decay exact;
  for (const auto& row : csv.rows) EXPECT_NEAR(row[1], exact.exact(row[0]), 1e-6);
  std::filesystem::remove(path);
}

TEST(Csv, AWriteTheWriterCouldNotDoIsAnError) {
  // /dev/full: every write fails with ENOSPC. The writer process reports it,
  // and the run fails with the reason, as a direct write would.
  detail::OutputFile out("/dev/full", detail::OutputFile::Rows::Whole);
  out.write("t,x\n");
  try {
    out.close();
    ADD_FAILURE() << "closing must report the failed write";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(Contains(e.what(), "writing to /dev/full failed: No space left on device")) << e.what();
  }
  Decay m;
  RunResult r = run(m, {"-o", "/dev/full", "--quiet"}, false);
  EXPECT_EQ(r.status, detail::kExitRunFailed) << r.err;
  EXPECT_TRUE(Contains(r.err, "writing to /dev/full failed: No space left on device")) << r.err;
}

}  // namespace
}  // namespace mbgrt::test
