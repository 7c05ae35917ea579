#include "common/process/stop_signals.h"

#include <array>
#include <atomic>
#include <csignal>

namespace mostar {
namespace {

std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void OnStopSignal(int) { g_stop_requested.store(true); }

constexpr int kMaxSignal = 64;
std::array<std::atomic<bool>, kMaxSignal + 1> g_signal_requests{};

extern "C" void OnRequestSignal(int signal_number) {
  if (signal_number > 0 && signal_number <= kMaxSignal) g_signal_requests[signal_number] = true;
}

bool IsRequestSignal(int signal_number) {
  return signal_number > 0 && signal_number <= kMaxSignal && signal_number != SIGINT &&
         signal_number != SIGTERM;
}

}  // namespace

void InstallStopSignals() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool StopRequested() { return g_stop_requested.load(); }
void RequestStop() { g_stop_requested.store(true); }

bool InstallSignalRequest(int signal_number) {
  if (!IsRequestSignal(signal_number)) return false;
  struct sigaction action {};
  action.sa_handler = OnRequestSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  return sigaction(signal_number, &action, nullptr) == 0;
}

bool TakeSignalRequest(int signal_number) {
  if (!IsRequestSignal(signal_number)) return false;
  return g_signal_requests[signal_number].exchange(false);
}

}  // namespace mostar
