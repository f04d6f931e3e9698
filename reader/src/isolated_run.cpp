#include "isolated_run.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <thread>
#include <utility>
#include <vector>

namespace mlce::reader::detail {
namespace {

using Clock = std::chrono::steady_clock;

constexpr char kReturned = 'R', kThrew = 'E';
constexpr std::size_t kHeader = 1 + sizeof(std::uint64_t);  // tag, payload length

/// Writes all of `n` bytes (a pipe takes them in pieces); false when the reader is gone.
bool write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

[[noreturn]] void run_child(const std::function<std::string()>& work, int fd) {
  // A crash report of a library the parent names in one message is noise, and the child's output
  // is the parent's to give: stdout and stderr go nowhere.
  if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, 1), ::dup2(null, 2), ::close(null);
  char tag = kReturned;
  std::string payload;
  try {
    payload = work();
  } catch (const std::exception& e) {
    tag = kThrew, payload = e.what();
  } catch (...) {
    tag = kThrew, payload = "an exception of an unknown type";
  }
  char header[kHeader];
  header[0] = tag;
  const std::uint64_t length = payload.size();
  std::memcpy(header + 1, &length, sizeof length);
  const bool sent = write_all(fd, header, kHeader) && write_all(fd, payload.data(), payload.size());
  ::_exit(sent ? 0 : 1);
}

/// Kills the child and reaps it (no zombie left behind).
void kill_and_reap(pid_t pid) {
  ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
}

}  // namespace

IsolatedOutcome run_isolated(const std::function<std::string()>& work, double seconds) {
  IsolatedOutcome out;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return out;  // not_run
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]), ::close(fds[1]);
    return out;  // not_run
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_child(work, fds[1]);
  }
  ::close(fds[1]);
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  auto time_left_ms = [&] {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return static_cast<int>(std::clamp<long long>(left, 0, 1000));
  };
  auto give_up = [&](IsolatedOutcome::Kind kind) {
    ::close(fds[0]);
    kill_and_reap(pid);
    out.kind = kind;
    return out;
  };

  // Read the frame as it comes, until the child closes the pipe (by exiting or dying). Polled
  // rather than waited on with an alarm: no signal handler of the caller's is touched.
  std::string frame;
  std::vector<char> chunk(1 << 16);
  for (;;) {
    if (Clock::now() >= deadline) return give_up(IsolatedOutcome::Kind::timed_out);
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, time_left_ms());
    if (ready < 0 && errno != EINTR) return give_up(IsolatedOutcome::Kind::not_run);
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], chunk.data(), chunk.size());
    if (n > 0) {
      frame.append(chunk.data(), static_cast<std::size_t>(n));
    } else if (n == 0) {
      break;  // end of file: the child has closed its end
    } else if (errno != EINTR && errno != EAGAIN) {
      return give_up(IsolatedOutcome::Kind::not_run);
    }
  }
  ::close(fds[0]);

  // The child closed its end on its way out: reap it.
  int status = 0;
  bool reaped = false;
  auto pause = std::chrono::microseconds(200);
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) {
      reaped = true;
      break;
    }
    if (done < 0 && errno != EINTR) break;  // not ours to wait for (SIGCHLD ignored: reaped on its own)
    if (Clock::now() >= deadline) {
      kill_and_reap(pid);
      out.kind = IsolatedOutcome::Kind::timed_out;
      return out;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }

  std::uint64_t length = 0;
  if (frame.size() >= kHeader) std::memcpy(&length, frame.data() + 1, sizeof length);
  const bool whole = frame.size() >= kHeader && (frame[0] == kReturned || frame[0] == kThrew) &&
                     length == frame.size() - kHeader;
  const bool exited_cleanly = !reaped || (WIFEXITED(status) && WEXITSTATUS(status) == 0);
  if (whole && exited_cleanly) {
    const bool returned = frame[0] == kReturned;
    out.kind = returned ? IsolatedOutcome::Kind::finished : IsolatedOutcome::Kind::threw;
    frame.erase(0, kHeader);  // in place: a large result is not copied
    (returned ? out.output : out.message) = std::move(frame);
    return out;
  }
  out.kind = IsolatedOutcome::Kind::crashed;
  if (reaped && WIFSIGNALED(status)) out.signal = WTERMSIG(status);
  if (reaped && WIFEXITED(status)) out.status = WEXITSTATUS(status);
  return out;
}

}  // namespace mlce::reader::detail
