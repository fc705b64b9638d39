#include "sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "progress.hpp"
#include "simulate.hpp"

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
  row += r.ok ? ",ok" : ",failed";
  for (std::size_t j = 0; j < outputs; ++j) {
    if (r.ranges.rows > 0)
      row += fmt::format(",{},{},{}", r.ranges.final[j], r.ranges.min[j], r.ranges.max[j]);
    else
      row += ",,,";
  }
  return row + fmt::format(",{:.3g},{}\n", r.wall_s, r.message.empty() ? std::string() : quoted(r.message));
}

}  // namespace

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

int run_sweep(const Model& prototype, const Options& o, OutputFile& summary) {
  SweepPlan plan;
  try {
    plan = o.sweep_file.empty() ? grid_plan(o.sweep) : read_sweep_file(o.sweep_file);
  } catch (const std::runtime_error& e) {
    print_error(e.what());
    return kExitUsage;
  }
  // Names and solver checked once, on an instance of its own, before any case runs.
  std::unique_ptr<Model> probe = prototype.make_new();
  if (!probe) {
    print_error(fmt::format("model '{}' cannot make new instances of itself (Model::make_new): regenerate it with "
                            "this version of mbgc to run a sweep",
                            prototype.name()));
    return kExitUsage;
  }
  if (!apply_overrides(*probe, o) || !check_model_fits(*probe, o)) return kExitUsage;
  for (std::size_t i = 0; i < plan.names.size(); ++i)
    if (!probe->set_parameter(plan.names[i], plan.cases[0][i])) {
      std::string known;
      for (const ParameterInfo& p : probe->parameters()) known += (known.empty() ? "" : ", ") + p.name;
      print_error(fmt::format("{}: unknown parameter '{}'; known parameters: {}",
                              o.sweep_file.empty() ? "--sweep" : "--sweep-file " + o.sweep_file, plan.names[i],
                              known.empty() ? "(none)" : known));
      return kExitUsage;
    }
  if (!o.case_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.case_dir, ec);
    if (ec || !std::filesystem::is_directory(o.case_dir)) {
      print_error(fmt::format("--case-dir {}: cannot create the directory{}", o.case_dir, ec ? ": " + ec.message() : ""));
      return kExitUsage;
    }
  }

  const std::size_t n = plan.cases.size();
  const std::vector<std::string> outputs = prototype.output_names();
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t jobs = std::min<std::size_t>(o.jobs > 0 ? o.jobs : cores, n);

  std::vector<CaseResult> results(n);
  std::atomic<std::size_t> next{0};
  std::size_t finished = 0, failed = 0;  // under `lock`
  std::mutex lock;
  std::condition_variable changed;
  auto worker = [&] {
    for (std::size_t k; (k = next++) < n;) {
      CaseResult r = run_case(prototype, o, plan, k);
      {
        std::lock_guard<std::mutex> hold(lock);
        failed += r.ok ? 0 : 1;
        ++finished;
        results[k] = std::move(r);
      }
      changed.notify_one();
    }
  };

  const auto started = std::chrono::steady_clock::now();
  std::vector<std::thread> threads;
  for (std::size_t j = 0; j < jobs; ++j) threads.emplace_back(worker);
  ProgressLine progress(is_terminal(stderr) && !o.quiet);
  try {
    summary.write(summary_header(plan, outputs));
    // rows in case order, each as soon as it and every case before it is done
    std::unique_lock<std::mutex> hold(lock);
    for (std::size_t written = 0; written < n;) {
      changed.wait_for(hold, std::chrono::milliseconds(100), [&] { return results[written].done; });
      while (written < n && results[written].done) {
        summary.write(summary_row(plan, written, results[written], outputs.size()));
        results[written].ranges = {};  // the row is out: keep no more than it
        ++written;
      }
      progress.update(static_cast<double>(finished) / static_cast<double>(n),
                      fmt::format("sweep: {} of {} cases done{}", finished, n,
                                  failed ? fmt::format(", {} failed", failed) : std::string()));
    }
  } catch (...) {
    next = n;  // the workers take no new case
    for (std::thread& t : threads) t.join();
    throw;
  }
  for (std::thread& t : threads) t.join();
  progress.clear();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!o.quiet)
    fmt::print(stderr, "mbgrt: sweep of model '{}': {} case{} on {} thread{} in {}; {}\n", prototype.name(), n,
               n == 1 ? "" : "s", jobs, jobs == 1 ? "" : "s", format_duration(wall_s),
               failed ? fmt::format("{} failed (the summary's message column says why)", failed)
                      : std::string("all ran to the end"));
  return failed ? kExitRunFailed : kExitSuccess;
}

}  // namespace mbgrt::detail
