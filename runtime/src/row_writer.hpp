// The writer process behind OutputFile::Rows::Whole (csv.hpp): a process of
// its own writes the simulator's text out, whole lines only, so that a
// simulator killed by SIGKILL leaves a file of whole rows holding every row
// it finished.
#pragma once

#include <sys/types.h>

#include <string>
#include <string_view>

namespace mbgrt::detail {

class RowWriter {
 public:
  /// Forks the writer process, which writes to `fd` from now on (this process
  /// need not keep its copy); `name` is the destination in messages. Only in
  /// a process with one thread. Throws std::runtime_error if it cannot start.
  RowWriter(int fd, std::string name);
  /// finish(), its error swallowed.
  ~RowWriter();
  RowWriter(const RowWriter&) = delete;
  RowWriter& operator=(const RowWriter&) = delete;

  /// Sends `text` to the writer over the socket. Throws std::runtime_error
  /// once the writer has stopped (a failed write: what stopped it).
  void write(std::string_view text);
  /// Lets the writer write out every whole line and end, and waits for it.
  /// Throws std::runtime_error if it could not. Idempotent.
  void finish();

 private:
  void wait_for_writer();

  std::string name_;
  int socket_ = -1;  ///< our end of the socket to the writer
  pid_t pid_ = -1;   ///< the writer process, until waited for
};

}  // namespace mbgrt::detail
