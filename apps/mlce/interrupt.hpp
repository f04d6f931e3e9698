#pragma once
// Scratch files removed when the run is interrupted (Ctrl-C, kill, a closed terminal): outputs are
// written to temporaries that only a finished command renames into place, and an interrupted one
// must leave none of them behind either.
#include <string>
#include <vector>

namespace mlce::cli {

/// SIGINT, SIGTERM and SIGHUP remove every registered scratch file, then end the process by the
/// same signal (its default action, so the shell sees the usual status: 130 for Ctrl-C).
void remove_scratch_files_on_interrupt();

/// Registers `path` (or several) as scratch for its lifetime. At most 64 at once; more are not
/// removed on interrupt (never more than a handful are open).
class ScratchGuard {
 public:
  ScratchGuard() = default;
  explicit ScratchGuard(const std::string& path) { add(path); }
  explicit ScratchGuard(const std::vector<std::string>& paths) {
    for (const auto& p : paths) add(p);
  }
  ScratchGuard(const ScratchGuard&) = delete;
  ScratchGuard& operator=(const ScratchGuard&) = delete;
  ~ScratchGuard();
  void add(const std::string& path);

 private:
  std::vector<int> slots_;
};

}  // namespace mlce::cli
