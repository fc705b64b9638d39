// timing.hpp — shared by the hand-written models in bench/modal.
#pragma once

#include <algorithm>
#include <chrono>

namespace bench_modal {

/// The fastest wall time of f(), over at least 3 runs and min_total_s seconds.
template <class F>
double fastest_of(F&& f, double min_total_s = 0.3) {
  double best = 1e300, total = 0;
  for (int rep = 0; rep < 3 || total < min_total_s; ++rep) {
    const auto start = std::chrono::steady_clock::now();
    f();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = std::min(best, s), total += s;
  }
  return best;
}

}  // namespace bench_modal
