#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace mbgrt::detail {

bool is_terminal(std::FILE* f) { return f && isatty(fileno(f)) == 1; }

ProgressLine::ProgressLine(bool enabled, std::FILE* out)
    : enabled_(enabled), out_(out), start_(Clock::now()), last_(start_) {}

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  if (seconds < 10) return fmt::format("{:.2g} s", seconds);
  const long s = std::lround(seconds);
  if (s < 60) return fmt::format("{} s", s);
  if (s < 3600) return fmt::format("{} min {:02} s", s / 60, s % 60);
  return fmt::format("{} h {:02} min", s / 3600, (s % 3600) / 60);
}

std::string ProgressLine::text(double fraction, double elapsed_s, const std::string& what) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  std::string line = fmt::format("{} ({:.0f} %)", what, 100 * fraction);
  // the rate so far, once there is one to speak of
  if (fraction > 0.001 && elapsed_s > 0.5) line += ", " + format_duration(elapsed_s * (1 - fraction) / fraction) + " left";
  return line;
}

void ProgressLine::update(double fraction, const std::string& what) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (drawn_ > 0 && std::chrono::duration<double>(now - last_).count() < kEvery) return;
  if (drawn_ == 0 && std::chrono::duration<double>(now - start_).count() < kEvery) return;  // a short run shows nothing
  last_ = now;
  const std::string line = text(fraction, std::chrono::duration<double>(now - start_).count(), what);
  // pad with blanks over what a longer previous line left
  fmt::print(out_, "\r{:<{}}", line, std::max(line.size(), drawn_));
  std::fflush(out_);
  drawn_ = std::max(line.size(), drawn_);
}

void ProgressLine::clear() {
  if (!enabled_ || drawn_ == 0) return;
  fmt::print(out_, "\r{:<{}}\r", "", drawn_);
  std::fflush(out_);
  drawn_ = 0;
}

}  // namespace mbgrt::detail
