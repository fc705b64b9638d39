// chain_peers — the planar chain of examples/chain (N = 2, 8, 32, 100; 1 s
// from 0.3 rad at every joint) simulated by mbgc's generated code, a
// hand-written O(N) recursive model, MuJoCo, Simbody and DART, side by side
// in one process (harness.hpp measures).
//
// For each engine and N: the largest RK4 step h = 2^-k s whose joint angles at
// t = 1 s are within 1e-6 rad of the reference, then the wall time of a 1 s
// run at that step (the fastest of repeats filling at least 0.3 s). The
// reference is the hand-written model at h = 2^-16 s, checked against mbgc's
// code at the same step (they must agree to 1e-9 rad, or the run stops).
//
//   chain_peers OUT.csv      # one row per (N, engine); a table on stdout
#include <cstdio>
#include <fstream>
#include <iostream>

#include "engine.hpp"
#include "harness.hpp"

namespace {

constexpr double kTargetError_rad = 1e-6;

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: chain_peers OUT.csv\n";
    return 2;
  }
  std::ofstream csv(argv[1]);
  csv << "n,engine,step_s,steps,error_rad,run_s,us_per_step,ratio_to_mbgc\n";
  std::printf("%4s  %-20s %10s %8s %10s %12s %10s\n", "N", "engine", "step_s", "steps", "error_rad", "run_s", "vs mbgc");
  for (int n : {2, 8, 32, 100}) {
    std::vector<bench::Engine> engines = {bench::mbgc_engine(n), bench::recursive_engine(n), bench::mujoco_engine(n),
                                          bench::simbody_engine(n), bench::dart_engine(n)};
    using bench::kReferenceExponent;
    const long ref_steps = 1L << kReferenceExponent;
    const std::vector<double> reference = engines[1].run(1.0 / ref_steps, ref_steps);
    const double cross_check = bench::max_difference(engines[0].run(1.0 / ref_steps, ref_steps), reference);
    if (!(cross_check <= 1e-9)) {
      std::fprintf(stderr, "N = %d: mbgc and the hand-written model differ by %.3g rad at h = 2^-%d s: not the same model\n",
                   n, cross_check, kReferenceExponent);
      return 1;
    }
    double mbgc_s = 0;
    for (const bench::Engine& e : engines) {
      const bench::Measured m = bench::measure(e, reference, kTargetError_rad);
      if (&e == &engines[0]) mbgc_s = m.run_s;
      const long steps = 1L << m.exponent;
      const double ratio = m.run_s / mbgc_s;
      csv << n << ',' << e.name << (m.reached ? "" : " (not within 1e-6 rad)") << ',' << 1.0 / steps << ',' << steps
          << ',' << m.error << ',' << m.run_s << ','
          << 1e6 * m.run_s / steps << ',' << ratio << '\n';
      std::printf("%4d  %-20s %10.3g %8ld %10.2g %12.4g %9.2fx%s\n", n, e.name.c_str(), 1.0 / steps, steps, m.error,
                  m.run_s, ratio, m.reached ? "" : "  (did not reach 1e-6)");
    }
    std::printf("      (mbgc against the hand-written reference at h = 2^-%d s: %.2g rad)\n", kReferenceExponent,
                cross_check);
  }
  return 0;
}
