// interrupt.hpp — the signals that ask a run to stop (Ctrl-C's SIGINT,
// SIGTERM from kill or a batch system, SIGHUP from a closed terminal),
// caught so that the run stops between two rows instead of inside one: the
// CSV it leaves holds whole rows only. A second signal of the same kind
// ends the process at once, as if nothing were caught. SIGKILL cannot be
// caught: a run killed by it may leave a last row without its newline.
#pragma once

#include <atomic>
#include <csignal>
#include <initializer_list>
#include <vector>

namespace mbgrt::detail {

/// While alive, `signals` are caught; stop_signal() names the first caught.
/// One scope at a time (the process's signal dispositions are global).
class StopSignals {
 public:
  explicit StopSignals(std::initializer_list<int> signals);
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// The first signal caught since the scope began; 0 if none.
  static int caught();
  /// The flag itself, for a run to poll between rows.
  static const std::atomic<int>& flag();

 private:
  std::vector<std::pair<int, void (*)(int)>> previous_;
};

/// "SIGINT (Ctrl-C)", "SIGTERM", "SIGHUP", or "a signal" for any other.
const char* signal_name(int signal);

}  // namespace mbgrt::detail
