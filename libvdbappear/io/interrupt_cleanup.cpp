#include "libvdbappear/io/interrupt_cleanup.h"

#include <array>
#include <atomic>
#include <csignal>
#include <mutex>
#include <unistd.h>

namespace vdbappear {

namespace {

constexpr int kSlots = 64;  // outputs alive at once in one process; tools have one or two
std::array<std::atomic<const char*>, kSlots> g_paths{};
constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};

extern "C" void removeTemporariesAndRaise(int signal_number) {
  for (auto& slot : g_paths)
    if (const char* path = slot.exchange(nullptr)) unlink(path);
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

void installHandlers() {
  for (const int s : kSignals) {
    struct sigaction action {};
    action.sa_handler = removeTemporariesAndRaise;
    sigemptyset(&action.sa_mask);
    struct sigaction previous {};
    sigaction(s, nullptr, &previous);
    if (previous.sa_handler == SIG_IGN) continue;  // a signal the caller ignores stays ignored (nohup)
    sigaction(s, &action, nullptr);
  }
}

}  // namespace

int registerInterruptCleanup(const char* path) {
  static std::once_flag installed;
  std::call_once(installed, installHandlers);
  for (int i = 0; i < kSlots; ++i) {
    const char* expected = nullptr;
    if (g_paths[std::size_t(i)].compare_exchange_strong(expected, path)) return i;
  }
  return -1;
}

void unregisterInterruptCleanup(int slot) {
  if (slot >= 0 && slot < kSlots) g_paths[std::size_t(slot)].store(nullptr);
}

}  // namespace vdbappear
