// chain_peers — the planar chain of examples/chain (N = 2, 8, 32; 1 s from
// 0.3 rad at every joint) simulated by mbgc's generated code, a hand-written
// O(N) recursive model, MuJoCo and Simbody, side by side in one process.
//
// For each engine and N: the largest RK4 step h = 2^-k s whose joint angles at
// t = 1 s are within 1e-6 rad of the reference, then the wall time of a 1 s
// run at that step (the fastest of repeats filling at least 0.3 s). The
// reference is the hand-written model at h = 2^-16 s, checked against mbgc's
// code at the same step (they must agree to 1e-9 rad, or the run stops).
//
//   chain_peers OUT.csv      # one row per (N, engine); a table on stdout
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "engine.hpp"

namespace {

constexpr double kTargetError_rad = 1e-6;
constexpr int kReferenceExponent = 16;  // reference step 2^-16 s
constexpr double kMinTiming_s = 0.3;

/// Largest |a_i - b_i|; infinite if any entry is not finite (a run that blew up).
double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
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
  double error_rad = 0, run_s = 0;
};

Measured measure(const bench::Engine& e, const std::vector<double>& reference) {
  Measured m;
  for (m.exponent = 2; m.exponent <= kReferenceExponent - 2; ++m.exponent) {
    const long steps = 1L << m.exponent;
    try {
      m.error_rad = max_difference(e.run(1.0 / steps, steps), reference);
    } catch (const std::exception&) {  // Simbody refuses a NaN state once a step too large has blown up
      m.error_rad = std::numeric_limits<double>::infinity();
    }
    if (m.error_rad <= kTargetError_rad) break;
  }
  const long steps = 1L << m.exponent;
  double total = 0, best = std::numeric_limits<double>::infinity();
  for (int rep = 0; rep < 3 || total < kMinTiming_s; ++rep) {
    const auto start = std::chrono::steady_clock::now();
    volatile double sink = e.run(1.0 / steps, steps)[0];
    (void)sink;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    total += s;
    best = std::min(best, s);
  }
  m.run_s = best;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: chain_peers OUT.csv\n";
    return 2;
  }
  std::ofstream csv(argv[1]);
  csv << "n,engine,step_s,steps,error_rad,run_s,us_per_step,ratio_to_mbgc\n";
  std::printf("%4s  %-20s %10s %8s %10s %12s %10s\n", "N", "engine", "step_s", "steps", "error_rad", "run_s", "vs mbgc");
  for (int n : {2, 8, 32}) {
    std::vector<bench::Engine> engines = {bench::mbgc_engine(n), bench::recursive_engine(n), bench::mujoco_engine(n),
                                          bench::simbody_engine(n)};
    const long ref_steps = 1L << kReferenceExponent;
    const std::vector<double> reference = engines[1].run(1.0 / ref_steps, ref_steps);
    const double cross_check = max_difference(engines[0].run(1.0 / ref_steps, ref_steps), reference);
    if (!(cross_check <= 1e-9)) {
      std::fprintf(stderr, "N = %d: mbgc and the hand-written model differ by %.3g rad at h = 2^-%d s: not the same model\n",
                   n, cross_check, kReferenceExponent);
      return 1;
    }
    double mbgc_s = 0;
    for (const bench::Engine& e : engines) {
      const Measured m = measure(e, reference);
      if (&e == &engines[0]) mbgc_s = m.run_s;
      const long steps = 1L << m.exponent;
      const double ratio = m.run_s / mbgc_s;
      csv << n << ',' << e.name << ',' << 1.0 / steps << ',' << steps << ',' << m.error_rad << ',' << m.run_s << ','
          << 1e6 * m.run_s / steps << ',' << ratio << '\n';
      std::printf("%4d  %-20s %10.3g %8ld %10.2g %12.4g %9.2fx%s\n", n, e.name.c_str(), 1.0 / steps, steps, m.error_rad,
                  m.run_s, ratio, m.error_rad <= kTargetError_rad ? "" : "  (did not reach 1e-6)");
    }
    std::printf("      (mbgc against the hand-written reference at h = 2^-%d s: %.2g rad)\n", kReferenceExponent,
                cross_check);
  }
  return 0;
}
