#include "row_writer.hpp"

#include <fmt/format.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace mbgrt::detail {

namespace {

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

/// The writer process: copies `from` to `to` up to the last newline
/// received; what follows it when `from` closes (a row the simulator was
/// killed in the middle of) is dropped. Exits 0, or with the errno of a
/// failed write.
[[noreturn]] void write_whole_lines(int from, int to) {
  // A stop the terminal sends the whole process group is for the simulator,
  // which ends after a whole row and then closes the socket.
  for (int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_IGN);
  // Hold no other descriptor: another output's writer must see its socket
  // close when the simulator dies, and a copy here would keep it open.
  std::array<int, 5> keep{0, 1, 2, from, to};
  std::sort(keep.begin(), keep.end());
  unsigned next = 0;
  for (int k : keep) {
    if (static_cast<unsigned>(k) > next) ::close_range(next, static_cast<unsigned>(k) - 1, 0);
    next = std::max(next, static_cast<unsigned>(k) + 1);
  }
  ::close_range(next, ~0U, 0);
  std::string pending;  // the process had one thread when it forked: allocating is safe
  std::array<char, 1 << 16> buf;
  for (;;) {
    const ssize_t n = ::read(from, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) ::_exit(errno);
    if (n == 0) ::_exit(0);
    pending.append(buf.data(), static_cast<std::size_t>(n));
    const std::size_t end = pending.rfind('\n');
    if (end == std::string::npos) continue;
    if (!write_all(to, pending.data(), end + 1)) ::_exit(errno != 0 ? errno : EIO);
    pending.erase(0, end + 1);
  }
}

}  // namespace

RowWriter::RowWriter(int fd, std::string name) : name_(std::move(name)) {
  auto cannot_start = [&](int e) {
    return std::runtime_error(fmt::format("cannot start the writer of {}: {}", name_, std::strerror(e)));
  };
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
    write_whole_lines(ends[1], fd);
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
  while (!text.empty()) {
    // MSG_NOSIGNAL: a writer that stopped is an error to report, not a SIGPIPE
    const ssize_t k = ::send(socket_, text.data(), text.size(), MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) {
      const int e = errno;
      wait_for_writer();  // throws what stopped it, if it failed
      throw std::runtime_error(fmt::format("writing to {} failed: {}", name_, std::strerror(e)));
    }
    text.remove_prefix(static_cast<std::size_t>(k));
  }
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
