#include "row_writer.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <new>
#include <stdexcept>
#include <utility>

namespace mbgrt::detail {

/// The memory the simulator and its writer share (mmap MAP_SHARED, made
/// before the fork). Byte i of the text sits at data[i % kRingBytes]; the
/// counts only grow (2^64 bytes outlast any run). The simulator alone writes
/// `committed` and the bytes past it, the writer alone `consumed`, `failed`
/// and nothing of `data`; each count is on a cache line of its own, so that
/// one process's stores do not slow the other's loads of the other count.
struct Ring {
  // Lock-free atomics are address-free: both processes use the variable in
  // the shared page itself, not a lock that would live in one of them.
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
  static_assert(std::atomic<int>::is_always_lock_free);

  /// Bytes copied in, stored (release) after the copy: the writer never
  /// takes a byte the simulator is still copying, even if it was killed then.
  alignas(64) std::atomic<std::uint64_t> committed{0};
  /// Bytes copied out, stored (release) after the copy: the simulator never
  /// overwrites a byte the writer has not taken.
  alignas(64) std::atomic<std::uint64_t> consumed{0};
  /// The errno of the write the writer failed, set before it ends, so that
  /// the simulator stops at its next write as if it had written itself.
  alignas(64) std::atomic<int> failed{0};
  alignas(64) char data[RowWriter::kRingBytes];
};

namespace {

/// How long the writer sleeps between looks at the ring when nothing wakes
/// it. Nothing has to for the rows' sake: they are safe in the ring, and a
/// dying simulator's socket wakes the writer to write them. So the period
/// only bounds how late a row reaches the file for someone following it
/// (`tail -f`, a plot of a --realtime run): 5 ms is within a 60 Hz
/// display's frame (17 ms). A wake-up costs a few microseconds, some 0.1 %
/// of a core at 200 a second; and with the ring emptied every 5 ms only a
/// simulator writing more than 200 MB/s of CSV text (its MiB in 5 ms) ever
/// finds it full.
constexpr int kDrainPeriod_ms = 5;

bool write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::write(fd, p, n);
    if (k < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}

/// Closes every descriptor but 0, 1, 2, `a` and `b`.
void keep_only(int a, int b) {
  std::array<int, 5> keep{0, 1, 2, a, b};
  std::sort(keep.begin(), keep.end());
  unsigned next = 0;
  for (int k : keep) {
    if (static_cast<unsigned>(k) > next) ::close_range(next, static_cast<unsigned>(k) - 1, 0);
    next = std::max(next, static_cast<unsigned>(k) + 1);
  }
  ::close_range(next, ~0U, 0);
}

sigset_t just_sigpipe() {
  sigset_t s;
  sigemptyset(&s);
  sigaddset(&s, SIGPIPE);
  return s;
}

/// The writer failed to write: says so in the ring, then ends. A write into
/// a pipe nobody reads (stdout piped into `head`) raised SIGPIPE, held back
/// until now: let go, it ends the writer, and the simulator follows
/// (wait_for_writer), as writing itself it would have ended.
[[noreturn]] void stop_writing(Ring& ring, int error) {
  if (error == 0) error = EIO;
  ring.failed.store(error, std::memory_order_release);
  const sigset_t sigpipe = just_sigpipe();
  ::sigprocmask(SIG_UNBLOCK, &sigpipe, nullptr);
  ::_exit(error);
}

/// Appends the ring's bytes [from, to) to `text`.
void take(const Ring& ring, std::uint64_t from, std::uint64_t to, std::string& text) {
  const std::size_t at = from % RowWriter::kRingBytes;
  const std::size_t n = to - from;
  const std::size_t first = std::min(n, RowWriter::kRingBytes - at);
  text.append(ring.data + at, first);
  text.append(ring.data, n - first);  // the rest wrapped around to the start
}

/// The writer process: every kDrainPeriod_ms, or when the simulator wakes it
/// over `socket`, takes what the ring holds and writes it to `to` up to the
/// last newline. When the socket closes (the simulator closed it, or died) it
/// takes the rest, writes it up to the last newline and exits 0: what follows
/// (a row the simulator was killed in the middle of) is dropped. On a failed
/// write, exits with its errno.
[[noreturn]] void write_whole_lines(Ring& ring, int socket, int to) {
  // A stop the terminal sends the whole process group is for the simulator,
  // which ends after a whole row and then closes the socket.
  for (int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_IGN);
  const sigset_t sigpipe = just_sigpipe();
  ::sigprocmask(SIG_BLOCK, &sigpipe, nullptr);  // until stop_writing has told the simulator
  // Hold no other descriptor: another output's writer must see its socket
  // close when the simulator dies, and a copy here would keep it open.
  keep_only(socket, to);
  std::string pending;  // the process had one thread when it forked: allocating is safe
  std::uint64_t taken = 0;
  for (bool open = true; open;) {
    pollfd ready{socket, POLLIN, 0};
    ssize_t wakes = 0;  // the simulator found the ring full and waits for an answer
    if (::poll(&ready, 1, kDrainPeriod_ms) > 0) {
      std::array<char, 64> bytes;
      wakes = ::read(socket, bytes.data(), bytes.size());
      // EOF, or ECONNRESET if it died before reading an answer: the
      // simulator is gone either way, and what it finished is in the ring
      if (wakes == 0 || (wakes < 0 && errno != EINTR)) open = false;
    }
    const std::uint64_t end = ring.committed.load(std::memory_order_acquire);
    take(ring, taken, end, pending);
    taken = end;
    ring.consumed.store(taken, std::memory_order_release);
    if (wakes > 0) {
      // Answered before writing: the simulator fills the ring again meanwhile.
      // MSG_NOSIGNAL: SIGPIPE is for the output; a simulator that died since
      // is seen at the next poll.
      static constexpr std::array<char, 64> answers{};
      ::send(socket, answers.data(), static_cast<std::size_t>(wakes), MSG_NOSIGNAL);
    }
    const std::size_t whole = pending.rfind('\n');
    if (whole == std::string::npos) continue;
    if (!write_all(to, pending.data(), whole + 1)) stop_writing(ring, errno);
    pending.erase(0, whole + 1);
  }
  ::_exit(0);
}

}  // namespace

RowWriter::RowWriter(int fd, std::string name) : name_(std::move(name)) {
  auto cannot_start = [&](int e) {
    if (ring_) ::munmap(ring_, sizeof(Ring));
    return std::runtime_error(fmt::format("cannot start the writer of {}: {}", name_, std::strerror(e)));
  };
  // MAP_POPULATE: the ring's pages are made now, before the run's clock
  // starts, not one page fault at a time as the rows first fill them (the
  // car's 800 rows met some 40 faults, 0.3 ms of a 9 ms run)
  void* shared = ::mmap(nullptr, sizeof(Ring), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS | MAP_POPULATE, -1, 0);
  if (shared == MAP_FAILED) throw cannot_start(errno);
  ring_ = new (shared) Ring;  // the counts zero
  int ends[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) throw cannot_start(errno);
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(ends[0]);
    ::close(ends[1]);
    throw cannot_start(e);
  }
  if (pid == 0) {
    ::close(ends[0]);
    write_whole_lines(*ring_, ends[1], fd);
  }
  ::close(ends[1]);
  socket_ = ends[0];
  pid_ = pid;
}

RowWriter::~RowWriter() {
  try {
    finish();
  } catch (const std::runtime_error&) {
    // an error written out already, or one nobody asked about
  }
}

void RowWriter::write(std::string_view text) {
  if (pid_ < 0) throw std::runtime_error(fmt::format("writing to {} after it was closed", name_));
  if (ring_->failed.load(std::memory_order_relaxed) != 0) writer_stopped(0);
  while (!text.empty()) {
    const std::uint64_t free = kRingBytes - (committed_ - ring_->consumed.load(std::memory_order_acquire));
    if (free == 0) {
      wait_for_space();
      continue;
    }
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(free, text.size()));
    const std::size_t at = committed_ % kRingBytes;
    const std::size_t first = std::min(n, kRingBytes - at);
    std::memcpy(ring_->data + at, text.data(), first);
    std::memcpy(ring_->data, text.data() + first, n - first);  // the rest wraps around to the start
    committed_ += n;
    ring_->committed.store(committed_, std::memory_order_release);
    text.remove_prefix(n);
  }
}

/// The ring is full: wakes the writer with a byte on the socket and sleeps in
/// recv() until it answers, which it does after taking what the ring held.
void RowWriter::wait_for_space() {
  char byte = 0;
  ssize_t k = 0;
  // MSG_NOSIGNAL: a writer that stopped is an error to report, not a SIGPIPE
  while ((k = ::send(socket_, &byte, 1, MSG_NOSIGNAL)) < 0 && errno == EINTR) {
  }
  if (k == 1)
    while ((k = ::recv(socket_, &byte, 1, 0)) < 0 && errno == EINTR) {
    }
  if (k != 1) writer_stopped(k < 0 ? errno : EPIPE);  // EOF: the writer ended
}

/// Throws what stopped the writer (or `error`, ours, if it says nothing).
void RowWriter::writer_stopped(int error) {
  wait_for_writer();  // throws what stopped it, if it failed
  throw std::runtime_error(fmt::format("writing to {} failed: {}", name_,
                                       error != 0 ? std::strerror(error) : "its writer process ended"));
}

void RowWriter::finish() {
  if (pid_ >= 0) wait_for_writer();
}

/// Closes our end of the socket (the writer then writes what is left and
/// ends), waits for the writer and throws unless it wrote everything. A
/// writer killed by SIGPIPE (stdout piped into `head`, say) ends this
/// process the same way, as writing itself would have.
void RowWriter::wait_for_writer() {
  ::close(socket_);
  socket_ = -1;
  int status = 0;
  const pid_t pid = pid_;
  pid_ = -1;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  ::munmap(ring_, sizeof(Ring));
  ring_ = nullptr;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGPIPE) {
    std::signal(SIGPIPE, SIG_DFL);
    std::raise(SIGPIPE);
  }
  throw std::runtime_error(
      WIFEXITED(status)
          ? fmt::format("writing to {} failed: {}", name_, std::strerror(WEXITSTATUS(status)))
          : fmt::format("writing to {} failed: its writer process ended by signal {}", name_, WTERMSIG(status)));
}

}  // namespace mbgrt::detail
