// progress.hpp — one line on stderr that says how far a long run (or a
// sweep) has come and how long it has left, rewritten in place. Only when
// stderr is a terminal: a log file or a pipe never sees it. The line is
// rewritten at most every kEvery seconds, so a fast run pays a clock read per
// output point and nothing else, and is cleared before anything else is
// printed on stderr.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace mbgrt::detail {

/// true if `f` is a terminal (isatty).
bool is_terminal(std::FILE* f);

class ProgressLine {
 public:
  /// Draws on `out` when `enabled` (the caller decides: a terminal, not --quiet).
  ProgressLine(bool enabled, std::FILE* out = stderr);
  ~ProgressLine() { clear(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  bool enabled() const { return enabled_; }
  /// Fraction done in [0, 1], and what to say before the time left ("t = 2.5 s of 10 s").
  /// Redraws if kEvery has passed since the last drawing.
  void update(double fraction, const std::string& what);
  /// Erases the line (idempotent).
  void clear();
  /// The text update() would draw for `fraction` done after `elapsed_s` (for tests).
  static std::string text(double fraction, double elapsed_s, const std::string& what);

  static constexpr double kEvery = 0.25;  ///< s between redraws

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  std::FILE* out_;
  Clock::time_point start_, last_;
  std::size_t drawn_ = 0;  ///< characters on the line now
};

/// "1 h 02 min", "3 min 05 s", "12 s", "0.4 s".
std::string format_duration(double seconds);

}  // namespace mbgrt::detail
