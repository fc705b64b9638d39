// harness.hpp — what chain_peers and tree_peers do with an Engine: find the
// largest step 2^-k s whose result at t = 1 s is within a tolerance of a
// reference, and time a 1 s run at that step.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <vector>

#include "engine.hpp"

namespace bench {

constexpr int kReferenceExponent = 16;  // reference step 2^-16 s
constexpr double kMinTiming_s = 0.3;

/// Largest |a_i - b_i|; infinite if any entry is not finite (a run that blew up)
/// or the sizes differ.
inline double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = std::abs(a[i] - b[i]);
    if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
    m = std::max(m, d);
  }
  return m;
}

struct Measured {
  int exponent = 0;  // h = 2^-exponent s
  double error = 0, run_s = 0;
  bool reached = false;
  std::vector<double> errors;  // the error at h = 2^-2, 2^-3, ... 2^-exponent s
};

/// Tries h = 2^-2 ... 2^-max_exponent s until the result is within `target`
/// of `reference`, then times a 1 s run at that step (the fastest of at least
/// three repeats filling kMinTiming_s). If no step reaches the target, the
/// smallest one tried is timed and `reached` is false.
inline Measured measure(const Engine& e, const std::vector<double>& reference, double target,
                        int max_exponent = kReferenceExponent - 2) {
  Measured m;
  for (m.exponent = 2; m.exponent <= max_exponent; ++m.exponent) {
    const long steps = 1L << m.exponent;
    try {
      m.error = max_difference(e.run(1.0 / steps, steps), reference);
    } catch (const std::exception&) {  // Simbody refuses a NaN state once a step too large has blown up
      m.error = std::numeric_limits<double>::infinity();
    }
    m.errors.push_back(m.error);
    if (m.error <= target) break;
  }
  m.reached = m.error <= target;
  if (!m.reached) m.exponent = max_exponent;
  const long steps = 1L << m.exponent;
  double total = 0, best = std::numeric_limits<double>::infinity();
  for (int rep = 0; rep < 3 || total < kMinTiming_s; ++rep) {
    const auto start = std::chrono::steady_clock::now();
    try {
      volatile double sink = e.run(1.0 / steps, steps)[0];
      (void)sink;
    } catch (const std::exception&) {  // (a step that did not reach the target and blew up)
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    total += s;
    best = std::min(best, s);
  }
  m.run_s = best;
  return m;
}

}  // namespace bench
