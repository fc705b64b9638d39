#include "interrupt.hpp"

namespace mbgrt::detail {

namespace {

std::atomic<int> caught_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "set from a signal handler");

extern "C" void on_stop_signal(int signal) {
  int none = 0;
  caught_signal.compare_exchange_strong(none, signal);
  std::signal(signal, SIG_DFL);  // the same signal again ends the process at once
}

}  // namespace

StopSignals::StopSignals(std::initializer_list<int> signals) {
  caught_signal = 0;
  for (int s : signals) previous_.emplace_back(s, std::signal(s, on_stop_signal));
}

StopSignals::~StopSignals() {
  for (auto it = previous_.rbegin(); it != previous_.rend(); ++it) std::signal(it->first, it->second);
}

int StopSignals::caught() { return caught_signal.load(); }
const std::atomic<int>& StopSignals::flag() { return caught_signal; }

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT (Ctrl-C)";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

}  // namespace mbgrt::detail
