// driver_output_test.cpp — where mbgc writes its C++: a regular file through
// a temporary and a rename (a failed write leaves no partial file), but a
// device or a pipe in place (`-o /dev/null` must not replace the device with
// a file), and through a symbolic link into its target.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "driver/driver.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mbgc_driver_output_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

int compile_to(const fs::path& out) {
  mbgc::driver::Options opt;
  opt.input = std::string(MBGC_SOURCE_DIR) + "/tests/golden/good/dc_motor.mbg";
  opt.output = out.string();
  std::ostringstream sout, serr;
  return mbgc::driver::compile(opt, sout, serr);
}

}  // namespace

TEST(DriverOutput, APipeIsWrittenInPlaceNotReplacedByAFile) {
  const fs::path pipe = scratch("pipe") / "model.cpp";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  // a reader first (non-blocking: the writer's open then returns at once); the
  // dc motor's C++ fits the pipe's buffer, so the writer never waits for it
  const int reader = ::open(pipe.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  EXPECT_EQ(compile_to(pipe), 0);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::read(reader, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(n));
  ::close(reader);
  EXPECT_TRUE(fs::is_fifo(pipe)) << "the pipe was replaced by a file";
  EXPECT_NE(text.find("class dc_motor_model"), std::string::npos) << "the C++ did not go through the pipe";
  fs::remove_all(pipe.parent_path());
}

TEST(DriverOutput, ASymbolicLinkStaysALinkToTheNewText) {
  const fs::path dir = scratch("link");
  const fs::path target = dir / "real.cpp", link = dir / "model.cpp";
  { std::ofstream(target) << "old"; }
  fs::create_symlink(target, link);
  EXPECT_EQ(compile_to(link), 0);
  EXPECT_TRUE(fs::is_symlink(link));
  std::ifstream in(target);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_NE(s.str().find("class dc_motor_model"), std::string::npos);
  fs::remove_all(dir);
}
