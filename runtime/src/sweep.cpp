#include "sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "interrupt.hpp"
#include "progress.hpp"
#include "simulate.hpp"
#include "sweep_cluster.hpp"

namespace mbgrt::detail {

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const auto comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

/// What a run writes on a FILE* (its report), kept in memory.
class Capture {
 public:
  Capture() : f_(open_memstream(&buffer_, &size_)) {
    if (!f_) throw std::runtime_error("cannot open a memory stream for a case's report");
  }
  ~Capture() {
    std::fclose(f_);
    std::free(buffer_);
  }
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  std::FILE* get() const { return f_; }
  std::string text() {
    std::fflush(f_);
    return std::string(buffer_, size_);
  }

 private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* f_;
};

/// The first error line of a run's report, without "mbgrt: error: ".
std::string first_error(const std::string& report) {
  const std::string prefix = "mbgrt: error: ";
  auto at = report.find(prefix);
  const auto from = at == std::string::npos ? 0 : at + prefix.size();
  std::string line = trim(report.substr(from, report.find('\n', from) - from));
  return line.empty() ? std::string("the run failed") : line;
}

struct CaseResult {
  bool done = false;
  bool ok = false;
  bool not_run = false;  // the sweep was interrupted before this case started
  OutputRanges ranges;
  double wall_s = 0;
  std::string message;
};

std::string case_path(const std::string& dir, std::size_t k, std::size_t total, const char* extension) {
  const int width = std::max(4, static_cast<int>(fmt::format("{}", total).size()));
  return fmt::format("{}/case_{:0{}}.{}", dir, k + 1, width, extension);
}

CaseResult run_case(const Model& prototype, const Options& o, const SweepPlan& plan, std::size_t k) {
  CaseResult r;
  const auto started = std::chrono::steady_clock::now();
  Capture report;
  {
    ErrorRedirect redirect(report.get());
    try {
      std::unique_ptr<Model> model = prototype.make_new();
      bool ready = apply_overrides(*model, o);
      for (std::size_t i = 0; ready && i < plan.names.size(); ++i)
        if (!model->set_parameter(plan.names[i], plan.cases[k][i])) {
          print_error(fmt::format("unknown parameter '{}'", plan.names[i]));
          ready = false;
        }
      if (ready) {
        Options one = o;
        one.quiet = o.case_dir.empty();  // the run summary only goes to a case's log
        OutputFile out(o.case_dir.empty() ? std::string("/dev/null") : case_path(o.case_dir, k, plan.cases.size(), "csv"));
        RunHooks hooks;
        hooks.report = report.get();
        hooks.ranges = &r.ranges;
        r.ok = simulate(*model, one, out, nullptr, nullptr, hooks) == kExitSuccess;
      }
    } catch (const std::exception& e) {
      print_error(e.what());
      r.ok = false;
    }
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const std::string text = report.text();
  if (!r.ok) r.message = first_error(text);
  if (!o.case_dir.empty()) {
    std::ofstream log(case_path(o.case_dir, k, plan.cases.size(), "log"));
    log << text;
  }
  r.done = true;
  return r;
}

std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

std::string summary_header(const SweepPlan& plan, const std::vector<std::string>& outputs) {
  std::string h = "case";
  for (const std::string& name : plan.names) h += "," + name;
  h += ",status";
  for (const std::string& out : outputs) h += fmt::format(",{0}_final,{0}_min,{0}_max", out);
  return h + ",wall_s,message\n";
}

std::string summary_row(const SweepPlan& plan, std::size_t k, const CaseResult& r, std::size_t outputs) {
  std::string row = fmt::format("{}", k + 1);
  for (double v : plan.cases[k]) row += fmt::format(",{}", v);
  row += r.not_run ? ",not_run" : r.ok ? ",ok" : ",failed";
  for (std::size_t j = 0; j < outputs; ++j) {
    if (r.ranges.rows > 0)
      row += fmt::format(",{},{},{}", r.ranges.final[j], r.ranges.min[j], r.ranges.max[j]);
    else
      row += ",,,";
  }
  return row + fmt::format(",{:.3g},{}\n", r.wall_s, r.message.empty() ? std::string() : quoted(r.message));
}

}  // namespace

std::vector<std::string> lines_in_case_order(const std::string& text, std::size_t total) {
  std::vector<std::string> lines(total);
  std::size_t start = 0;
  while (start < text.size()) {
    const auto end = std::min(text.find('\n', start), text.size());
    std::string line = text.substr(start, end - start);
    start = end + 1;
    std::size_t k = 0;
    auto [ptr, ec] = std::from_chars(line.data(), line.data() + line.size(), k);
    if (ec != std::errc() || k < 1 || k > total || !lines[k - 1].empty())
      throw std::runtime_error(fmt::format("sweep: a gathered row is not one of cases 1 to {} or came twice: {}", total, line));
    lines[k - 1] = std::move(line);
  }
  for (std::size_t k = 0; k < total; ++k)
    if (lines[k].empty()) throw std::runtime_error(fmt::format("sweep: no row came back for case {}", k + 1));
  return lines;
}

SweepPlan grid_plan(const std::vector<SweepAxis>& axes) {
  SweepPlan plan;
  std::size_t total = 1;
  for (const SweepAxis& a : axes) {
    plan.names.push_back(a.name);
    total *= static_cast<std::size_t>(a.count);
  }
  plan.cases.reserve(total);
  for (std::size_t c = 0; c < total; ++c) {
    std::vector<double> values(axes.size());
    std::size_t rest = c;
    for (std::size_t i = axes.size(); i-- > 0;) {
      const auto count = static_cast<std::size_t>(axes[i].count);
      values[i] = axes[i].value(static_cast<long>(rest % count));
      rest /= count;
    }
    plan.cases.push_back(std::move(values));
  }
  return plan;
}

SweepPlan read_sweep_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("--sweep-file {}: cannot open the file", path));
  SweepPlan plan;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> fields = split_fields(text);
    const std::string where = fmt::format("{}:{}", path, number);
    if (plan.names.empty()) {
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].empty())
          throw std::runtime_error(fmt::format("{}: the header's column {} has no parameter name", where, i + 1));
        for (std::size_t j = 0; j < i; ++j)
          if (fields[j] == fields[i])
            throw std::runtime_error(fmt::format("{}: parameter '{}' is named twice in the header", where, fields[i]));
      }
      plan.names = std::move(fields);
      continue;
    }
    if (fields.size() != plan.names.size())
      throw std::runtime_error(fmt::format("{}: {} value{}, but the header names {} parameter{}", where, fields.size(),
                                           fields.size() == 1 ? "" : "s", plan.names.size(),
                                           plan.names.size() == 1 ? "" : "s"));
    if (plan.cases.size() >= static_cast<std::size_t>(kMaxSweepCases))
      throw std::runtime_error(fmt::format("{}: more than the {} cases a sweep may run", where, kMaxSweepCases));
    std::vector<double> values(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const char* end = fields[i].data() + fields[i].size();
      auto [ptr, ec] = std::from_chars(fields[i].data(), end, values[i]);
      if (fields[i].empty() || ec != std::errc() || ptr != end || !std::isfinite(values[i]))
        throw std::runtime_error(
            fmt::format("{}: {} = '{}' is not a finite number", where, plan.names[i], fields[i]));
    }
    plan.cases.push_back(std::move(values));
  }
  if (plan.names.empty()) throw std::runtime_error(fmt::format("--sweep-file {}: no header (the parameter names)", path));
  if (plan.cases.empty()) throw std::runtime_error(fmt::format("--sweep-file {}: no cases after the header", path));
  return plan;
}

namespace {

/// The plan, checked before any case runs: the parameters known, the solver
/// fit for the model, the case directory made. nullopt after an error printed.
std::optional<SweepPlan> prepare(const Model& prototype, const Options& o) {
  SweepPlan plan;
  try {
    plan = o.sweep_file.empty() ? grid_plan(o.sweep) : read_sweep_file(o.sweep_file);
  } catch (const std::runtime_error& e) {
    print_error(e.what());
    return std::nullopt;
  }
  std::unique_ptr<Model> probe = prototype.make_new();  // an instance of its own
  if (!probe) {
    print_error(fmt::format("model '{}' cannot make new instances of itself (Model::make_new): regenerate it with "
                            "this version of mbgc to run a sweep",
                            prototype.name()));
    return std::nullopt;
  }
  if (!apply_overrides(*probe, o) || !check_model_fits(*probe, o)) return std::nullopt;
  for (std::size_t i = 0; i < plan.names.size(); ++i)
    if (!probe->set_parameter(plan.names[i], plan.cases[0][i])) {
      std::string known;
      for (const ParameterInfo& p : probe->parameters()) known += (known.empty() ? "" : ", ") + p.name;
      print_error(fmt::format("{}: unknown parameter '{}'; known parameters: {}",
                              o.sweep_file.empty() ? "--sweep" : "--sweep-file " + o.sweep_file, plan.names[i],
                              known.empty() ? "(none)" : known));
      return std::nullopt;
    }
  if (!o.case_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.case_dir, ec);
    if (ec || !std::filesystem::is_directory(o.case_dir)) {
      print_error(fmt::format("--case-dir {}: cannot create the directory{}", o.case_dir, ec ? ": " + ec.message() : ""));
      return std::nullopt;
    }
  }
  return plan;
}

/// Runs the cases `mine` (indices into plan.cases) on `jobs` threads and
/// calls `finished(k, result)` on this thread for each, in the order of
/// `mine`, as soon as it and every case before it is done. Returns how many failed.
std::size_t run_cases(const Model& prototype, const Options& o, const SweepPlan& plan,
                      const std::vector<std::size_t>& mine, std::size_t jobs, ProgressLine& progress,
                      const std::function<void(std::size_t, const CaseResult&)>& finished) {
  const std::size_t n = mine.size();
  std::vector<CaseResult> results(n);
  std::atomic<std::size_t> next{0};
  std::size_t done = 0, failed = 0;  // under `lock`
  std::mutex lock;
  std::condition_variable changed;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < n;) {
      CaseResult r;
      if (StopSignals::caught() != 0) {  // Ctrl-C: the cases running finish, no new one starts
        r.done = r.not_run = true;
        r.message = "not run: the sweep was interrupted (Ctrl-C) before it started";
      } else {
        r = run_case(prototype, o, plan, mine[i]);
      }
      {
        std::lock_guard<std::mutex> hold(lock);
        failed += r.ok || r.not_run ? 0 : 1;
        ++done;
        results[i] = std::move(r);
      }
      changed.notify_one();
    }
  };
  std::vector<std::thread> threads;
  for (std::size_t j = 0; j < std::min(jobs, n); ++j) threads.emplace_back(worker);
  try {
    std::unique_lock<std::mutex> hold(lock);
    for (std::size_t written = 0; written < n;) {
      changed.wait_for(hold, std::chrono::milliseconds(100), [&] { return results[written].done; });
      for (; written < n && results[written].done; ++written) {
        finished(mine[written], results[written]);
        results[written].ranges = {};  // reported: keep no more than that
      }
      progress.update(static_cast<double>(done) / static_cast<double>(n),
                      fmt::format("sweep: {} of {} cases done{}", done, n,
                                  failed ? fmt::format(", {} failed", failed) : std::string()));
    }
  } catch (...) {
    next = n;  // the workers take no new case
    for (std::thread& t : threads) t.join();
    throw;
  }
  for (std::thread& t : threads) t.join();
  progress.clear();
  return failed;
}

}  // namespace

int run_sweep(const Model& prototype, const Options& o, OutputFile& summary) {
  Cluster cluster;  // one process, or this rank's share of an MPI launch
  // Every rank checks the same things; rank 0 alone says what is wrong.
  std::FILE* quiet = cluster.rank() == 0 ? nullptr : std::fopen("/dev/null", "w");
  std::optional<ErrorRedirect> silent;
  if (quiet) silent.emplace(quiet);
  std::optional<SweepPlan> plan = prepare(prototype, o);
  silent.reset();
  if (quiet) std::fclose(quiet);
  if (!plan) return kExitUsage;

  const std::size_t n = plan->cases.size(), ranks = static_cast<std::size_t>(cluster.size());
  std::vector<std::size_t> mine;  // round robin over the ranks
  for (std::size_t k = static_cast<std::size_t>(cluster.rank()); k < n; k += ranks) mine.push_back(k);
  // threads: one per core alone; under MPI the ranks are the parallelism unless --jobs says otherwise
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t jobs = std::max<std::size_t>(1, o.jobs > 0 ? o.jobs : ranks > 1 ? 1 : cores);
  const std::vector<std::string> outputs = prototype.output_names();
  ProgressLine progress(cluster.rank() == 0 && is_terminal(stderr) && !o.quiet);

  const auto started = std::chrono::steady_clock::now();
  std::size_t failed = 0, not_run = 0;
  StopSignals ctrl_c({SIGINT});
  if (ranks == 1) {
    summary.write(summary_header(*plan, outputs));
    failed = run_cases(prototype, o, *plan, mine, jobs, progress, [&](std::size_t k, const CaseResult& r) {
      summary.write(summary_row(*plan, k, r, outputs.size()));
      not_run += r.not_run ? 1 : 0;
    });
  } else {
    std::string rows;  // this rank's, one line per case
    failed = run_cases(prototype, o, *plan, mine, jobs, progress, [&](std::size_t k, const CaseResult& r) {
      rows += summary_row(*plan, k, r, outputs.size());
      not_run += r.not_run ? 1 : 0;
    });
    const std::vector<std::string> all = cluster.gather_lines(rows, n);  // rank 0: every case's, in case order
    failed = static_cast<std::size_t>(cluster.sum(static_cast<long>(failed)));
    not_run = static_cast<std::size_t>(cluster.sum(static_cast<long>(not_run)));
    if (cluster.rank() == 0) {
      std::string text = summary_header(*plan, outputs);
      for (const std::string& line : all) text += line + "\n";
      summary.write(text);
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!o.quiet && cluster.rank() == 0)
    fmt::print(stderr, "mbgrt: sweep of model '{}': {} case{} on {}{} thread{} in {}; {}\n", prototype.name(), n,
               n == 1 ? "" : "s", ranks > 1 ? fmt::format("{} MPI ranks x ", ranks) : std::string(), jobs,
               jobs == 1 ? "" : "s", format_duration(wall_s),
               failed ? fmt::format("{} failed (the summary's message column says why)", failed)
                      : not_run ? std::string("none failed") : std::string("all ran to the end"));
  if (not_run > 0 && cluster.rank() == 0)  // said even with --quiet: the summary is not whole
    fmt::print(stderr, "mbgrt: sweep interrupted (Ctrl-C): {} of {} case{} not run (status not_run in the summary); "
               "the {} finished are kept\n", not_run, n, n == 1 ? "" : "s", n - not_run);
  if (not_run > 0) return kExitInterrupted;
  return failed ? kExitRunFailed : kExitSuccess;
}

}  // namespace mbgrt::detail
