#include "realtime.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <thread>

namespace mbgrt::detail {

Pacer::Pacer(double factor, double t0, std::size_t frames) : factor_(factor), t0_(t0) {
  compute_s_.reserve(frames + 1);
  start_ = frame_start_ = Clock::now();
}

void Pacer::frame_done(double t) {
  const Clock::time_point now = Clock::now();
  if (compute_s_.empty()) {
    // the first point is the initial state: the wall clock starts with it
    compute_s_.push_back(std::chrono::duration<double>(now - frame_start_).count());
    start_ = frame_start_ = now;
    t0_ = t;
    return;
  }
  if (compute_s_.size() < compute_s_.capacity())
    compute_s_.push_back(std::chrono::duration<double>(now - frame_start_).count());
  const auto due = start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>((t - t0_) / factor_));
  if (now > due) {
    ++overruns_;
    latest_s_ = std::max(latest_s_, std::chrono::duration<double>(now - due).count());
  } else {
    std::this_thread::sleep_until(due);
  }
  frame_start_ = Clock::now();
}

std::string Pacer::summary() const {
  std::vector<double> sorted = compute_s_;
  if (sorted.size() > 1) sorted.erase(sorted.begin());  // the first point is the start, not a frame
  // after the first 10 frames: the first ones pay for cold caches and lazy binding
  const double settled = sorted.size() > 10 ? *std::max_element(sorted.begin() + 10, sorted.end()) : 0;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted.empty() ? 0 : sorted[sorted.size() / 2], worst = sorted.empty() ? 0 : sorted.back();
  std::string s = fmt::format("paced at {:g}x the wall clock: {} overrun{} of {} points", factor_, overruns_,
                              overruns_ == 1 ? "" : "s", compute_s_.size());
  if (overruns_ > 0) s += fmt::format(" (latest by {:.3g} s)", latest_s_);
  s += fmt::format("; compute per frame: median {:.3g} s, worst {:.3g} s", median, worst);
  if (sorted.size() > 10) s += fmt::format(" ({:.3g} s after the first 10)", settled);
  return s;
}

}  // namespace mbgrt::detail
