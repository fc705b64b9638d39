// Bad input never crashes the compiler: every good model, cut short at many
// points and with bytes replaced, must give exit status 0 or 1 with either
// output or a diagnostic — never a signal (under the sanitizer build, never a
// sanitizer report) and never a partial output file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "driver/driver.hpp"

namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> accepted;  // generated sources of mutants mbgc accepted

void compile_text(const std::string& text, const std::string& what) {
  fs::path dir = fs::temp_directory_path() / "mbgc_robustness";
  fs::create_directories(dir);
  fs::path model = dir / "mutant.mbg";
  fs::path out = dir / "mutant.cpp";
  fs::remove(out);
  { std::ofstream(model) << text; }
  mbgc::driver::Options opt;
  opt.input = model.string();
  opt.output = out.string();
  std::ostringstream sout, serr;
  int status = mbgc::driver::compile(opt, sout, serr);
  ASSERT_TRUE(status == 0 || status == 1) << what << ": status " << status;
  if (status == 1) {
    EXPECT_FALSE(fs::exists(out)) << what << ": a failed compile left an output file";
    EXPECT_NE(serr.str().find("error:"), std::string::npos) << what << ": failed without a diagnostic";
  } else {
    EXPECT_TRUE(fs::exists(out)) << what;
    accepted.push_back(read(out));
  }
}

}  // namespace

TEST(Robustness, TruncatedAndMutatedModelsNeverCrash) {
  std::vector<fs::path> models;
  for (const auto& e : fs::directory_iterator(fs::path(MBGC_SOURCE_DIR) / "tests/golden/good"))
    if (e.path().extension() == ".mbg") models.push_back(e.path());
  std::sort(models.begin(), models.end());
  ASSERT_FALSE(models.empty());
  std::mt19937 rng(20261121);
  const std::string alphabet = "01IRC()[]{}.,:;=+-*/^->\n #\"abc";
  int runs = 0;
  for (const fs::path& p : models) {
    std::string text = read(p);
    // imports are relative to the model's folder; mutants live elsewhere
    if (text.find("import") != std::string::npos) continue;
    for (std::size_t cut = 0; cut < text.size(); cut += std::max<std::size_t>(1, text.size() / 40)) {
      compile_text(text.substr(0, cut), p.filename().string() + " cut at " + std::to_string(cut));
      ++runs;
    }
    for (int k = 0; k < 60; ++k) {
      std::string m = text;
      for (int j = 0; j < 3; ++j) {
        std::size_t at = rng() % m.size();
        m[at] = alphabet[rng() % alphabet.size()];
      }
      compile_text(m, p.filename().string() + " mutation " + std::to_string(k));
      ++runs;
    }
  }
  EXPECT_GT(runs, 300);
  // What mbgc accepts must compile: check a sample of the accepted mutants.
  std::sort(accepted.begin(), accepted.end());
  accepted.erase(std::unique(accepted.begin(), accepted.end()), accepted.end());
  std::shuffle(accepted.begin(), accepted.end(), rng);
  fs::path dir = fs::temp_directory_path() / "mbgc_robustness";
  int checked = 0;
  std::string files;
  for (const std::string& src : accepted) {
    if (checked == 20) break;
    fs::path cpp = dir / ("accepted" + std::to_string(checked) + ".cpp");
    { std::ofstream(cpp) << src; }
    files += " \"" + cpp.string() + "\"";
    ++checked;
  }
  std::string cmd = std::string(MBGC_CXX) + " -std=c++17 -fsyntax-only -Wall -Wextra -Werror -I\"" +
                    MBGC_SOURCE_DIR + "/runtime/include\"" + files;
  EXPECT_EQ(std::system(cmd.c_str()), 0) << "generated code does not compile: " << cmd;
  EXPECT_GT(checked, 0);
}
