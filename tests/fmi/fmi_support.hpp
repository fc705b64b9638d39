// Shared by the FMI tests: running the examples' simulators and fmusim, and
// comparing their CSV tables. Every file a test writes is its own (work()
// under a name the test chooses): ctest runs the tests side by side.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <ostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fmi_test {

struct Table {
  std::vector<std::string> header;  ///< names without quotes or units
  std::vector<std::vector<double>> rows;
};

inline std::string plain_name(std::string cell) {
  cell.erase(std::remove(cell.begin(), cell.end(), '"'), cell.end());
  if (const auto unit = cell.find(" ["); unit != std::string::npos) cell.erase(unit);
  return cell;
}

inline Table read_table(const std::string& path) {
  Table t;
  std::ifstream in(path);
  std::string line;
  if (std::getline(in, line)) {
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) t.header.push_back(plain_name(cell));
  }
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> row;
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
    t.rows.push_back(row);
  }
  return t;
}

inline int shell(const std::string& command) {
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// The FMU of an example (tests/fmi/CMakeLists.txt builds them).
inline std::string fmu_of(const std::string& name, int version = 3) {
  return std::string(FMU_DIR) + "/fmu" + std::to_string(version) + "_" + name + ".fmu";
}

inline std::string work(const std::string& name) { return std::string(WORK_DIR) + "/" + name; }

/// The example's own simulator: its rows (every output), or empty on failure.
inline Table native(const std::string& sim, const std::string& tag, const std::string& args = "") {
  const std::string csv = work(tag + ".native.csv");
  EXPECT_EQ(shell("\"" + sim + "\" --quiet " + args + " --out \"" + csv + "\" 2> \"" + work(tag + ".native.log") + "\""), 0)
      << slurp(work(tag + ".native.log"));
  return read_table(csv);
}

/// fmusim on the FMU: its rows, or empty on failure (the log says why).
inline Table imported(const std::string& fmu, const std::string& tag, const std::string& args) {
  const std::string csv = work(tag + ".csv"), log = work(tag + ".log");
  std::remove(csv.c_str());
  const int status = shell(std::string("\"") + FMUSIM + "\" " + args + " --output-file \"" + csv + "\" \"" + fmu +
                           "\" > \"" + log + "\" 2>&1");
  EXPECT_EQ(status, 0) << "fmusim " << args << " " << fmu << ":\n" << slurp(log);
  return read_table(csv);
}

/// The largest difference of an output between the two runs, over the native
/// rows, as a fraction of its scale: the output's largest size, but no less
/// than 1e-3 of the largest of all (an output that stays near 0, such as an
/// energy error, is measured against the model's sizes). Rows of `other` are
/// taken by time; where it has several at one time (before and after an
/// event), the last.
inline double worst_difference(const Table& reference, const Table& other, std::string& where, bool every_row = true) {
  // the same outputs in the same order (the time column's name differs)
  EXPECT_EQ(std::vector<std::string>(reference.header.begin() + (reference.header.empty() ? 0 : 1), reference.header.end()),
            std::vector<std::string>(other.header.begin() + (other.header.empty() ? 0 : 1), other.header.end()));
  std::map<double, const std::vector<double>*> at;
  for (const auto& row : other.rows) at[row[0]] = &row;
  const std::size_t columns = reference.header.size();
  std::vector<double> peak(columns, 0.0);
  double largest = 0;
  for (const auto& row : reference.rows)
    for (std::size_t c = 1; c < columns && c < row.size(); ++c) peak[c] = std::max(peak[c], std::abs(row[c]));
  for (std::size_t c = 1; c < columns; ++c) largest = std::max(largest, peak[c]);
  double worst = 0;
  std::size_t matched = 0;
  for (const auto& row : reference.rows) {
    // fmusim's times are sums of steps: within a rounding of the grid's
    auto it = at.lower_bound(row[0] - 1e-9 * std::max(1.0, std::abs(row[0])));
    if (it == at.end() || std::abs(it->first - row[0]) > 1e-9 * std::max(1.0, std::abs(row[0]))) continue;
    while (std::next(it) != at.end() && std::abs(std::next(it)->first - row[0]) <= 1e-9 * std::max(1.0, std::abs(row[0]))) ++it;
    ++matched;
    const std::vector<double>& o = *it->second;
    for (std::size_t c = 1; c < columns && c < o.size(); ++c) {
      const double scale = std::max(peak[c], 1e-3 * largest);
      const double d = scale > 0 ? std::abs(row[c] - o[c]) / scale : 0.0;
      if (d > worst || std::isnan(d)) {
        worst = std::isnan(d) ? HUGE_VAL : d;
        where = reference.header[c] + " at t = " + std::to_string(row[0]);
      }
    }
  }
  if (every_row)
    EXPECT_EQ(matched, reference.rows.size()) << "rows of the native run without a row of the FMU's at their time";
  else  // (fmusim's model exchange records an event within 1e-4 s of a grid point in its stead)
    EXPECT_GE(matched, reference.rows.size() * 99 / 100) << "rows of the native run without a row of the FMU's";
  return worst;
}

}  // namespace fmi_test
