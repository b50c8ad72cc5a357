#include "common/interrupt.h"

#include <signal.h>

#include <cstdlib>
#include <cstring>

namespace fs {

namespace {

std::atomic<int> gSignal{0};
std::atomic<bool> gFlag{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

extern "C" void onSignal(int signal) {
  int expected = 0;
  gSignal.compare_exchange_strong(expected, signal);
  gFlag.store(true);
}

}  // namespace

void installInterruptHandlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second signal takes the default action: immediate termination
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interruptSignal() { return gSignal.load(); }

const std::atomic<bool>& interruptFlag() { return gFlag; }

void requestInterrupt(int signal) { onSignal(signal); }

void clearInterrupt() {
  gSignal = 0;
  gFlag = false;
}

std::string signalName(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

void throwIfInterrupted(const std::string& detail) {
  if (const int s = interruptSignal()) throw Interrupted(s, detail);
}

void testInterruptPoint(const std::string& point) {
  static const char* env = std::getenv("FIRSTSHOT_TEST_INTERRUPT");
  if (!env) return;
  const std::string want(env);
  if (want == point) raise(SIGINT);
  else if (want == point + ":TERM") raise(SIGTERM);
}

}  // namespace fs
