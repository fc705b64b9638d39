// tree_peers — the 3-D models of the peer benchmark (tree_spec.hpp): the
// binary tree of 31 rods on ball and universal joints (binary_tree.mbg,
// gravity along -y) and the chain of 32 rods on ball joints started bent in
// 3-D (spherical_chain.mbg, gravity along -z), each 1 s from rest, simulated
// by mbgc's generated code (joint coordinates), a hand-written O(N)
// articulated-body model (tree_aba.hpp), MuJoCo, Simbody and DART, side by
// side in one process. What is compared: every rod's centre of mass, world
// axes, at t = 1 s (metres).
//
// Before anything is timed: every engine's initial centres of mass must match
// the hand-written model's to 1e-12 m (the same pose), and mbgc's result must
// match the hand-written model's at the same step, 2^-16 s, to 1e-9 m (the
// same model), or the run stops. The reference is the hand-written model at
// h = 2^-18 s. Then for each engine (harness.hpp): the largest step
// h = 2^-k s, k <= 16, within 1e-6 m of the reference, and the wall time of a
// 1 s run at that step. (The planar chain stops at 2^-14 s with its reference
// at 2^-16 s; here MuJoCo's RK4 needs finer steps, see the error trail the
// program prints.)
//
//   tree_peers binary_tree OUT.csv
//   tree_peers spherical_chain OUT.csv
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "harness.hpp"
#include "tree_engines.hpp"

namespace {

std::string shortest(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2g", x);
  return b;
}

constexpr double kTargetError_m = 1e-6;
constexpr double kSamePose_m = 1e-12;
constexpr double kSameModel_m = 1e-9;
constexpr int kTreeReferenceExponent = 18;  // the reference step, 2^-18 s
constexpr int kCrossCheckExponent = 16;     // mbgc against the hand-written model at 2^-16 s
constexpr int kMaxExponent = 16;            // steps tried: 2^-2 ... 2^-16 s

}  // namespace

int main(int argc, char** argv) {
  using namespace bench;
  if (argc != 3 || (std::strcmp(argv[1], "binary_tree") != 0 && std::strcmp(argv[1], "spherical_chain") != 0)) {
    std::cerr << "usage: tree_peers binary_tree|spherical_chain OUT.csv\n";
    return 2;
  }
  const bool binary = std::strcmp(argv[1], "binary_tree") == 0;
  const int n = binary ? 31 : 32;
  const tree::TreeSpec spec = binary ? tree::binary_tree_spec(n) : tree::spherical_chain_spec(n);
  std::vector<Engine> engines = {binary ? tree::mbgc_binary_tree_31() : tree::mbgc_spherical_chain_32(),
                                 tree::aba_engine(spec), tree::mujoco_engine(spec), tree::simbody_engine(spec),
                                 tree::dart_engine(spec)};
  std::printf("%s, N = %d: centres of mass at t = 1 s\n", spec.name.c_str(), n);

  const std::vector<double> start = engines[1].run(1.0, 0);
  for (const Engine& e : engines) {
    const double d = max_difference(e.run(1.0, 0), start);
    std::printf("  initial pose: %-20s %.2g m from the hand-written model's\n", e.name.c_str(), d);
    if (!(d <= kSamePose_m)) {
      std::fprintf(stderr, "%s: %s does not start in the hand-written model's pose (%.3g m): not the same model\n",
                   spec.name.c_str(), e.name.c_str(), d);
      return 1;
    }
  }
  // The reference: the hand-written model at 2^-18 s (its own error: less than its distance from the run at
  // 2^-17 s, printed); mbgc checked against the hand-written model at the same step, 2^-16 s.
  auto run_at = [](const Engine& e, int exponent) { return e.run(1.0 / (1L << exponent), 1L << exponent); };
  const std::vector<double> reference = run_at(engines[1], kTreeReferenceExponent);
  const double reference_change = max_difference(run_at(engines[1], kTreeReferenceExponent - 1), reference);
  std::printf("  reference: the hand-written model at h = 2^-%d s (%.2g m from its run at 2^-%d s)\n",
              kTreeReferenceExponent, reference_change, kTreeReferenceExponent - 1);
  const double cross_check =
      max_difference(run_at(engines[0], kCrossCheckExponent), run_at(engines[1], kCrossCheckExponent));
  std::printf("  mbgc against the hand-written model, both at h = 2^-%d s: %.2g m\n", kCrossCheckExponent, cross_check);
  if (!(cross_check <= kSameModel_m)) {
    std::fprintf(stderr, "%s: mbgc and the hand-written model differ by %.3g m at h = 2^-%d s: not the same model\n",
                 spec.name.c_str(), cross_check, kCrossCheckExponent);
    return 1;
  }

  std::ofstream csv(argv[2]);
  csv << "n,engine,step_s,steps,error_m,run_s,us_per_step,ratio_to_mbgc\n";
  std::printf("%4s  %-20s %10s %8s %10s %12s %10s\n", "N", "engine", "step_s", "steps", "error_m", "run_s", "vs mbgc");
  double mbgc_s = 0;
  std::string trail;
  for (const Engine& e : engines) {
    const Measured m = measure(e, reference, kTargetError_m, kMaxExponent);
    if (&e == &engines[0]) mbgc_s = m.run_s;
    const long steps = 1L << m.exponent;
    const double ratio = m.run_s / mbgc_s;
    // An engine that reaches 1e-6 m at no step tried says so in its name (and its error is the finest step's).
    csv << n << ',' << e.name << (m.reached ? "" : " (not within 1e-6 m)") << ',' << 1.0 / steps << ',' << steps << ','
        << m.error << ',' << m.run_s << ','
        << 1e6 * m.run_s / steps << ',' << ratio << '\n';
    std::printf("%4d  %-20s %10.3g %8ld %10.3g %12.4g %9.2fx%s\n", n, e.name.c_str(), 1.0 / steps, steps, m.error,
                m.run_s, ratio, m.reached ? "" : "  (did not reach 1e-6 m at any step tried)");
    trail += "    " + e.name + ":";
    for (double err : m.errors) trail += " " + shortest(err);
    trail += "\n";
  }
  std::printf("  error [m] at h = 2^-2, 2^-3, ... s, until 1e-6 m:\n%s", trail.c_str());
  return 0;
}
