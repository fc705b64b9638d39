// sim_run.hpp — shared by the numeric tests: run a generated simulator with
// options, read its CSV (and any other CSV it writes) back.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace numeric {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name || header[i].rfind(name + " [", 0) == 0) return i;  // `omega [rad/s]`
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
  /// Value of `name` in the row at time t (rows are on the communication grid).
  double at(double t, const std::string& name) const {
    std::size_t c = col(name);
    for (const auto& r : rows)
      if (std::abs(r[0] - t) < 1e-9) return r[c];
    ADD_FAILURE() << "no row at t = " << t;
    return NAN;
  }
  /// Largest |value| of a column over all rows.
  double max_abs(const std::string& name) const {
    std::size_t c = col(name);
    double m = 0;
    for (const auto& r : rows) m = std::max(m, std::abs(r[c]));
    return m;
  }
  /// Largest |value - first value| of a column over all rows.
  double max_deviation(const std::string& name) const {
    std::size_t c = col(name);
    double m = 0;
    for (const auto& r : rows) m = std::max(m, std::abs(r[c] - rows.front()[c]));
    return m;
  }
};

struct SimRun {
  int status = -1;
  Csv csv;
  std::string log;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A CSV file with a header line and numeric rows (empty if the file is missing).
inline Csv read_csv(const std::string& path) {
  Csv csv;
  std::ifstream in(path);
  std::string line;
  if (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) csv.header.push_back(cell);
  }
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::vector<double> row;
    // strtod, not stod: a subnormal value (1e-320, a force that has decayed
    // to nothing) is a number, but stod throws out_of_range on it
    while (std::getline(ss, cell, ',')) row.push_back(std::strtod(cell.c_str(), nullptr));
    csv.rows.push_back(row);
  }
  return csv;
}

/// Path of a scratch file for test `tag` in the numeric tests' build directory.
inline std::string work_file(const std::string& tag, const std::string& ext) {
  return std::string(WORK_DIR) + "/" + tag + ext;
}

/// Run a simulator with extra arguments; CSV to a file, summary to a log.
inline SimRun run(const std::string& sim, const std::string& args, const std::string& tag) {
  std::string csv = work_file(tag, ".csv");
  std::string log = work_file(tag, ".log");
  std::remove(csv.c_str());
  std::string cmd = "\"" + sim + "\" " + args + " --out \"" + csv + "\" 2> \"" + log + "\"";
  SimRun r;
  int raw = std::system(cmd.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.log = slurp(log);
  r.csv = read_csv(csv);
  return r;
}

/// Largest |a - b| of a column over the rows of two runs on the same grid.
inline double max_difference(const Csv& a, const Csv& b, const std::string& name) {
  EXPECT_EQ(a.rows.size(), b.rows.size());
  const std::size_t ca = a.col(name), cb = b.col(name);
  double m = 0;
  for (std::size_t i = 0; i < std::min(a.rows.size(), b.rows.size()); ++i) m = std::max(m, std::abs(a.rows[i][ca] - b.rows[i][cb]));
  return m;
}

inline double rel_err(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }


/// One classical RK4 step of y' = rates(y) (references written by hand in
/// the tests, independent of mbgc and SUNDIALS).
template <std::size_t N, class Rates>
std::array<double, N> rk4_step(const std::array<double, N>& y, double dt, Rates&& rates) {
  auto add = [](std::array<double, N> a, const std::array<double, N>& b, double h) {
    for (std::size_t i = 0; i < N; ++i) a[i] += h * b[i];
    return a;
  };
  const auto k1 = rates(y), k2 = rates(add(y, k1, dt / 2));
  const auto k3 = rates(add(y, k2, dt / 2)), k4 = rates(add(y, k3, dt));
  std::array<double, N> next = y;
  for (std::size_t i = 0; i < N; ++i) next[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  return next;
}

}  // namespace numeric
