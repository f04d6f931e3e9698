#include "interrupt.hpp"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>

namespace mlce::cli {
namespace {

// The handler may only call async-signal-safe functions (unlink, signal, raise) and read what
// it finds complete: each slot is published by its state after its path is written.
constexpr std::size_t kSlots = 64, kPathBytes = 4096;
enum : int { kFree = 0, kWriting = 1, kReady = 2 };
std::array<std::atomic<int>, kSlots> state{};
std::array<std::array<char, kPathBytes>, kSlots> paths{};

extern "C" void on_interrupt(int sig) {
  for (std::size_t k = 0; k < kSlots; ++k)
    if (state[k].load(std::memory_order_acquire) == kReady) ::unlink(paths[k].data());
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

void remove_scratch_files_on_interrupt() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

void ScratchGuard::add(const std::string& path) {
  if (path.size() >= kPathBytes) return;
  for (std::size_t k = 0; k < kSlots; ++k) {
    int expected = kFree;
    if (!state[k].compare_exchange_strong(expected, kWriting, std::memory_order_acq_rel)) continue;
    std::memcpy(paths[k].data(), path.c_str(), path.size() + 1);
    state[k].store(kReady, std::memory_order_release);
    slots_.push_back(static_cast<int>(k));
    return;
  }
}

ScratchGuard::~ScratchGuard() {
  for (int k : slots_) state[static_cast<std::size_t>(k)].store(kFree, std::memory_order_release);
}

}  // namespace mlce::cli
