// The writer process behind OutputFile::Rows::Whole (csv.hpp): the simulator
// copies its text into a ring of shared memory, and a process of its own
// writes it out, whole lines only, so that a simulator killed by SIGKILL
// leaves a file of whole rows holding every row it finished.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace mbgrt::detail {

struct Ring;  // the shared memory (row_writer.cpp)

class RowWriter {
 public:
  /// The ring's size. The writer empties it every few milliseconds, and a
  /// simulator would have to write 200 MB/s of CSV to fill it in between (the
  /// 14-DOF vehicle's 800 rows are 190 kB in all); one that does, or whose
  /// reader is slow, waits for the writer once a MiB, a round trip of a few
  /// syscalls that costs nothing beside formatting a MiB of numbers. Its
  /// pages are allocated on first touch, so a short run pays only for what
  /// its rows fill (a page fault per 4 kB), and prefaulting all of it would
  /// cost more than a run of a few thousand rows saves.
  static constexpr std::size_t kRingBytes = std::size_t{1} << 20;

  /// Forks the writer process, which writes to `fd` from now on (this process
  /// need not keep its copy); `name` is the destination in messages. Only in
  /// a process with one thread. Throws std::runtime_error if it cannot start.
  RowWriter(int fd, std::string name);
  /// finish(), its error swallowed.
  ~RowWriter();
  RowWriter(const RowWriter&) = delete;
  RowWriter& operator=(const RowWriter&) = delete;

  /// Copies `text` into the ring, in pieces if it is larger than what is free,
  /// waiting (asleep) for the writer while the ring is full. No syscall while
  /// there is room. Throws std::runtime_error once the writer has stopped
  /// (a failed write: what stopped it).
  void write(std::string_view text);
  /// Lets the writer write out every whole line and end, and waits for it.
  /// Throws std::runtime_error if it could not. Idempotent.
  void finish();

 private:
  void wait_for_space();
  [[noreturn]] void writer_stopped(int error);
  void wait_for_writer();

  std::string name_;
  Ring* ring_ = nullptr;
  int socket_ = -1;              ///< our end of the socket to the writer: its wake-ups, and its EOF
  pid_t pid_ = -1;               ///< the writer process, until waited for
  std::uint64_t committed_ = 0;  ///< what we have published: only this process writes the ring's count
};

}  // namespace mbgrt::detail
