// CSV layout (docs/cli.md, "Output and the run summary"): `t,<outputs>`
// header, one row per communication point from t_start to t_end, numbers that
// read back exactly.
#include <gtest/gtest.h>

#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <thread>

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

/// Rows `t,x` numbered 0, 1, ... until the text is `bytes` long or longer,
/// each some 100 bytes: a reader sees one missing, doubled or out of order.
std::string numbered_rows(std::size_t bytes) {
  std::string text = "t,x\n";
  for (long i = 0; text.size() < bytes; ++i)
    text += std::to_string(i) + ',' + std::string(90, static_cast<char>('a' + i % 26)) + '\n';
  return text;
}

constexpr std::size_t kRing = detail::RowWriter::kRingBytes;

TEST(Csv, AKilledSimulatorsFileHoldsEveryRowItFinishedWhenTheyOverfillTheRing) {
  // Three rings' worth of rows, one write() each: the simulator waits for the
  // writer whenever the ring is full, then dies with up to a ring's worth not
  // yet written out. It pauses once, after 0.7 of a ring, for the writer to
  // take that much: every take after it wraps around the ring's end.
  const std::string path = temp_path("killed_many.csv");
  const std::string text = numbered_rows(3 * kRing);
  run_and_kill([&] {
    detail::OutputFile out(path, detail::OutputFile::Rows::Whole);
    bool paused = false;
    for (std::size_t at = 0, end; at < text.size(); at = end + 1) {
      end = text.find('\n', at);
      out.write(std::string_view(text).substr(at, end + 1 - at));
      if (!paused && end > kRing * 7 / 10) {
        paused = true;
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
      }
    }
    out.write("123456,unfinished");
  });
  const std::string file = read_file(path);
  EXPECT_EQ(file.size(), text.size());
  EXPECT_TRUE(file == text) << "the rows differ from byte "
                            << std::mismatch(file.begin(), file.end(), text.begin(), text.end()).first - file.begin();
  std::filesystem::remove(path);
}

TEST(Csv, AWriteLargerThanTheRingIsWrittenWhole) {
  // One write() of two and a half rings, with a row longer than the ring
  // itself inside (the writer cannot wait for a newline the ring has no room
  // for): through close(), and through a SIGKILL right after the write.
  const std::string path = temp_path("large_write.csv");
  const std::string text = numbered_rows(kRing / 2) + std::string(kRing + 3, 'b') + "\n" + numbered_rows(kRing);
  {
    detail::OutputFile out(path, detail::OutputFile::Rows::Whole);
    out.write(text);
    out.close();
  }
  EXPECT_TRUE(read_file(path) == text) << "written and closed";
  run_and_kill([&] {
    detail::OutputFile out(path, detail::OutputFile::Rows::Whole);
    out.write(text + "0.5,unfinished");
  });
  EXPECT_TRUE(read_file(path) == text) << "written and killed";
  std::filesystem::remove(path);
}

/// A child process whose stdout is the pipe `ends` ([0] read, [1] write)
/// runs `body` and exits: 0, or 1 if body threw. Returns its pid (-1: no fork).
pid_t fork_writing_stdout_to(const int ends[2], const std::function<void()>& body) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  ::dup2(ends[1], 1);
  ::close(ends[0]);
  ::close(ends[1]);
  try {
    body();
  } catch (...) {
    ::_exit(1);
  }
  ::_exit(0);
}

TEST(Csv, ASimulatorWhoseReaderIsSlowWaitsForItAsleep) {
  // stdout is a pipe read 64 kB every 10 ms: the ring fills, and the
  // simulator sleeps until the writer has room for it. It gets every row,
  // and the simulator and its writer use a small part of a core meanwhile.
  const std::string text = numbered_rows(3 * kRing);
  int ends[2];
  ASSERT_EQ(::pipe(ends), 0);
  const pid_t pid = fork_writing_stdout_to(ends, [&] {
    detail::OutputFile out("-", detail::OutputFile::Rows::Whole);
    out.write(text);
    out.close();
  });
  ASSERT_GE(pid, 0);
  ::close(ends[1]);
  const auto started = std::chrono::steady_clock::now();
  std::string got;
  std::string chunk(1 << 16, '\0');
  for (ssize_t n; (n = ::read(ends[0], chunk.data(), chunk.size())) != 0;) {
    if (n < 0) continue;  // EINTR
    got.append(chunk.data(), static_cast<std::size_t>(n));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::close(ends[0]);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  int status = 0;
  rusage used{};
  ASSERT_EQ(::wait4(pid, &status, 0, &used), pid);  // its usage counts the writer's, which it waited for
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_TRUE(got == text) << got.size() << " bytes of " << text.size();
  const double cpu = static_cast<double>(used.ru_utime.tv_sec + used.ru_stime.tv_sec) +
                     static_cast<double>(used.ru_utime.tv_usec + used.ru_stime.tv_usec) * 1e-6;
  EXPECT_GT(elapsed, 0.3);  // 48 reads, 10 ms apart
  EXPECT_LT(cpu, 0.25 * elapsed) << "CPU time " << cpu << " s in " << elapsed << " s";
}

TEST(Csv, AWriteErrorStopsTheSimulatorAtItsNextWrite) {
  // The writer cannot write /dev/full: the simulator hears of it at a write
  // soon after, long before it would fill the ring, as when it wrote itself.
  detail::OutputFile out("/dev/full", detail::OutputFile::Rows::Whole);
  std::size_t written = 0;
  try {
    for (const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
         std::chrono::steady_clock::now() < until; std::this_thread::sleep_for(std::chrono::milliseconds(1))) {
      out.write("0,1\n");
      written += 4;
    }
    ADD_FAILURE() << "writing on for 5 s after the writer failed";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(Contains(e.what(), "writing to /dev/full failed: No space left on device")) << e.what();
  }
  EXPECT_LT(written, kRing / 100);
}

TEST(Csv, ASimulatorWritingIntoAClosedPipeEndsBySigpipeAtItsNextWrite) {
  // stdout piped into a reader that has gone (`sim | head`): the writer ends
  // by SIGPIPE, and so does the simulator at a write soon after.
  int ends[2];
  ASSERT_EQ(::pipe(ends), 0);
  const pid_t pid = fork_writing_stdout_to(ends, [] {
    detail::OutputFile out("-", detail::OutputFile::Rows::Whole);
    for (int i = 0; i < 5000; ++i) {
      out.write("0,1\n");
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    // (exits before close(), which would wait for the writer and end by SIGPIPE itself)
  });
  ASSERT_GE(pid, 0);
  ::close(ends[0]);
  ::close(ends[1]);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGPIPE) << status;
}

}  // namespace
}  // namespace mbgrt::test
