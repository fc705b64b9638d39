#include "harness.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace mbgrt::test {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string temp_path(const std::string& stem) {
  static int counter = 0;
  auto dir = std::filesystem::temp_directory_path() / "mbgrt-tests";
  std::filesystem::create_directories(dir);
  return (dir / (stem + "-" + std::to_string(::getpid()) + "-" + std::to_string(++counter)))
      .string();
}

namespace {

/// Sends file descriptor `fd` to a file until destroyed.
class Redirect {
 public:
  Redirect(int fd, const std::string& path) : fd_(fd), saved_(::dup(fd)) {
    int target = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (saved_ < 0 || target < 0) throw std::runtime_error("cannot redirect output for test");
    ::dup2(target, fd_);
    ::close(target);
  }
  ~Redirect() {
    ::dup2(saved_, fd_);
    ::close(saved_);
  }

 private:
  int fd_, saved_;
};

}  // namespace

RunResult run(Model& model, const std::vector<std::string>& args, bool with_out_file) {
  RunResult r;
  std::vector<std::string> argv_text{"sim"};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  if (with_out_file) {
    r.path = temp_path("out") + ".csv";
    argv_text.push_back("-o");
    argv_text.push_back(r.path);
  }
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);

  const std::string out_path = temp_path("stdout"), err_path = temp_path("stderr");
  std::cout.flush();
  std::fflush(nullptr);
  {
    Redirect out(1, out_path), err(2, err_path);
    r.status = mbgrt::run_main(model, static_cast<int>(argv_text.size()), argv.data());
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
  }
  r.out = read_file(out_path);
  r.err = read_file(err_path);
  if (std::getenv("MBGRT_TEST_SHOW_STDERR")) std::cout << r.err << std::flush;  // for debugging
  if (with_out_file && std::filesystem::exists(r.path)) {
    r.csv = read_file(r.path);
    std::filesystem::remove(r.path);
  }
  std::filesystem::remove(out_path);
  std::filesystem::remove(err_path);
  return r;
}

std::size_t Csv::column(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  throw std::out_of_range("no CSV column " + name);
}

Csv parse_csv(const std::string& text) {
  Csv csv;
  std::istringstream in(text);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream fields(line);
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    if (first) {
      csv.header = cells;
      first = false;
      continue;
    }
    std::vector<double> row;
    for (const std::string& c : cells) {
      char* end = nullptr;
      row.push_back(std::strtod(c.c_str(), &end));
      if (end != c.c_str() + c.size()) throw std::runtime_error("bad CSV number: " + c);
    }
    csv.rows.push_back(std::move(row));
  }
  return csv;
}

::testing::AssertionResult Contains(const std::string& text, const std::string& needle) {
  if (text.find(needle) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << needle << "' not found in:\n" << text;
}

long summary_number(const std::string& err, const std::string& label) {
  const auto pos = err.find("\n  " + label + " ");
  if (pos == std::string::npos) return -1;
  return std::strtol(err.c_str() + pos + 3 + label.size(), nullptr, 10);
}

double reported_time(const std::string& err) {
  // The summary may mention times too ("constraint drift: ... at t = 0.5 s").
  const std::string marker = "error: at t = ";
  const auto pos = err.find(marker);
  if (pos == std::string::npos) return std::nan("");
  return std::strtod(err.c_str() + pos + marker.size(), nullptr);
}

}  // namespace mbgrt::test
