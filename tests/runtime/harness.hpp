// Runs mbgrt::run_main in-process with an argv array and captures what it
// writes: the --out file, stdout and stderr (by redirecting file descriptors,
// so both stdio and iostreams are caught).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mbgrt/model.hpp"

namespace mbgrt::test {

struct RunResult {
  int status = -1;
  std::string csv;   ///< contents of the --out file ("" if none was written)
  std::string out;   ///< captured stdout
  std::string err;   ///< captured stderr
  std::string path;  ///< the --out path used
};

/// A fresh path in the temporary directory (the file is not created).
std::string temp_path(const std::string& stem);
/// The whole file ("" if it does not exist).
std::string read_file(const std::string& path);

/// Appends `-o <temp file>` unless `with_out_file` is false.
RunResult run(Model& model, const std::vector<std::string>& args, bool with_out_file = true);

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;

  std::size_t column(const std::string& name) const;  ///< throws if absent
  double at(std::size_t row, const std::string& name) const {
    return rows.at(row).at(column(name));
  }
};

Csv parse_csv(const std::string& text);

/// Like EXPECT_THAT(text, HasSubstr(needle)) without needing gmock; prints the text on failure.
::testing::AssertionResult Contains(const std::string& text, const std::string& needle);

/// The first number after `label` in the run summary (e.g. "steps"), or -1.
long summary_number(const std::string& err, const std::string& label);

/// The number after "error: at t = " in a stop message, or NaN.
double reported_time(const std::string& err);

}  // namespace mbgrt::test
