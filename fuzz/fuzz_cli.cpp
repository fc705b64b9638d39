// fuzz_cli — the simulator's command line (docs/cli.md) on a generated model
// (examples/dc_motor/dc_motor.mbg: six parameters to --set and --sweep). The
// input is the argument list, one argument per line. Parsing must end in
// options to run with or in exit status 0 (--help) or 2 (a usage error,
// reported); never a crash.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cli.hpp"
#include "fuzz_check.hpp"
#include "fuzz_cli_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> args = {"sim"};
  for (std::size_t start = 0; start <= text.size() && args.size() < 64;) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    args.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  fuzz_cli::dc_motor_model model;
  const mbgrt::detail::ParseOutcome outcome =
      mbgrt::detail::parse_command_line(model, static_cast<int>(args.size()), argv.data());
  using mbgrt::detail::kExitSuccess, mbgrt::detail::kExitUsage;
  mbgc::fuzz::check(outcome.options ? outcome.exit_status == kExitSuccess
                                    : (outcome.exit_status == kExitSuccess || outcome.exit_status == kExitUsage),
                    "parse_command_line's outcome is neither options, --help nor a usage error");
  return 0;
}
