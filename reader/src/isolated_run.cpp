#include "isolated_run.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <thread>

namespace mlce::reader::detail {

IsolatedOutcome run_isolated(const std::function<void()>& work, double seconds) {
  IsolatedOutcome out;
  const pid_t pid = ::fork();
  if (pid < 0) return out;  // not_run
  if (pid == 0) {
    // Its output is the parent's to give (the parent runs the work again), and a crash report of a
    // library the parent names in one message is noise: stdout and stderr go nowhere.
    if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, 1), ::dup2(null, 2), ::close(null);
    try {
      work();
    } catch (...) {  // the parent, running the work again, throws it
    }
    ::_exit(0);
  }
  // Polled rather than waited on with an alarm: no signal handler of the caller's is touched.
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  auto pause = std::chrono::microseconds(200);
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {  // not ours to wait for (SIGCHLD ignored: reaped on its own)
      ::kill(pid, SIGKILL);             // nothing is known; no child is left running
      return out;
    }
    if (Clock::now() >= deadline) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      out.kind = IsolatedOutcome::Kind::timed_out;
      return out;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    out.kind = IsolatedOutcome::Kind::finished;
  } else {
    out.kind = IsolatedOutcome::Kind::crashed;
    if (WIFSIGNALED(status)) out.signal = WTERMSIG(status);
    if (WIFEXITED(status)) out.status = WEXITSTATUS(status);
  }
  return out;
}

}  // namespace mlce::reader::detail
