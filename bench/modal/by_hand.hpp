// by_hand.hpp — shared by the hand-written models in bench/modal: timing, and
// one run of the simulator mbgc generated, under the same fixed-step RK4.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

/// What one run of a generated simulator gives: its CSV's last row (t first)
/// and the wall time from its run summary; empty and NaN if it failed.
struct GeneratedRun {
  std::vector<double> last_row;
  double wall_s = NAN;
};

/// Runs simulator `sim` from 0 to t_end s under RK4 with `steps` steps, one
/// CSV row at the end; `tag` names its scratch files in /tmp.
inline GeneratedRun run_generated(const std::string& sim, double t_end, long steps, const std::string& tag) {
  const std::string csv = "/tmp/" + tag + ".csv", log = "/tmp/" + tag + ".log";
  char cmd[1024];
  std::snprintf(cmd, sizeof cmd, "\"%s\" --t-end %g --interval %g --solver rk4 --step %.17g --out %s 2> %s", sim.c_str(),
                t_end, t_end, t_end / static_cast<double>(steps), csv.c_str(), log.c_str());
  GeneratedRun r;
  if (std::system(cmd) != 0) return r;
  std::ifstream in(csv);
  std::string line, last;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) last = line;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) r.last_row.push_back(std::strtod(cell.c_str(), nullptr));
  std::ifstream lg(log);
  while (std::getline(lg, line))
    if (line.rfind("  wall time", 0) == 0) r.wall_s = std::stod(line.substr(line.find_first_of("0123456789")));
  return r;
}

}  // namespace bench_modal
