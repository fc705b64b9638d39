// fuzz_compile — the whole compiler, text to C++ (mbgc model.mbg). The input
// is the model file; beside it lie the golden models' modal-data and mesh
// files and the files they import, so an input can name them. mbgc must
// answer 0 with C++ or 1 with an error; never crash, hang or run out of
// memory. The limits (ir/limits.hpp) are lowered so that every input
// compiles in milliseconds; the golden tests check the full ones.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "driver/driver.hpp"
#include "fuzz_check.hpp"

namespace fs = std::filesystem;

namespace {

fs::path work_dir;

void remove_work_dir() {
  std::error_code ec;
  fs::remove_all(work_dir, ec);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::string pattern = (fs::temp_directory_path() / "mbgc-fuzz-compile-XXXXXX").string();
  if (!mkdtemp(pattern.data())) std::abort();
  work_dir = pattern;
  std::atexit(remove_work_dir);
  for (const auto& e : fs::directory_iterator(fs::path(MBGC_SOURCE_DIR) / "tests/golden/good")) {
    const std::string ext = e.path().extension().string();
    if (ext == ".mbm" || ext == ".obj" || ext == ".mbg") fs::copy_file(e.path(), work_dir / e.path().filename());
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path model = work_dir / "fuzz_input.mbg";
  {
    std::ofstream out(model, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  mbgc::driver::Options opt;
  opt.input = model.string();
  opt.limits.loop_iterations = 1000;
  opt.limits.unrolled_work = 2000;
  opt.limits.model_size = 5000;
  std::ostringstream cpp, err;
  const int status = mbgc::driver::compile(opt, cpp, err);
  mbgc::fuzz::check(status == 0 || status == 1, "mbgc's exit status is neither 0 nor 1");
  if (status == 1) mbgc::fuzz::check(err.str().find("error:") != std::string::npos, "mbgc failed without an error");
  if (status == 0) mbgc::fuzz::check(!cpp.str().empty(), "mbgc succeeded without C++");
  return 0;
}
