// realtime.hpp — `--realtime [FACTOR]`: the run paced to the wall clock.
//
// The wall clock starts when the initial state's row is written (time t0).
// After each further point at simulated time t the run waits until the wall
// clock reaches that start + (t - t0) / FACTOR, so that rows appear as
// the simulated time passes (FACTOR 1: real time; 10: ten times faster). A
// point computed after its moment is an overrun. Each frame's compute time
// (from the end of the previous wait to the point, the solver's steps and
// the row) is kept, without allocating, for the median and the worst case.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace mbgrt::detail {

class Pacer {
 public:
  Pacer(double factor, double t0, std::size_t frames);
  /// The point at simulated time t is written: record the frame, then wait for its moment.
  void frame_done(double t);
  /// One line for the run summary.
  std::string summary() const;

 private:
  using Clock = std::chrono::steady_clock;
  double factor_, t0_;
  Clock::time_point start_, frame_start_;
  std::vector<double> compute_s_;  // per frame, reserved up front
  long overruns_ = 0;
  double latest_s_ = 0;  // the largest lateness of a point
};

}  // namespace mbgrt::detail
