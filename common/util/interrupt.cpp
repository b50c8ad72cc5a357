#include "common/util/interrupt.h"

#include <signal.h>
#include <time.h>

#include <cstdlib>
#include <cstring>

namespace firstshot {

namespace {

constexpr int64_t kDuplicateNs = 500000000;  ///< 0.5 s

std::atomic<int> gSignal{0};
std::atomic<bool> gFlag{false};
std::atomic<int64_t> gFirstNs{0};  ///< CLOCK_MONOTONIC time of the first signal
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free &&
                  std::atomic<int64_t>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

/// Only async-signal-safe calls: atomics, clock_gettime, signal, raise.
extern "C" void onSignal(int signal) {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  const int64_t now = int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
  int expected = 0;
  if (gSignal.compare_exchange_strong(expected, signal)) {
    gFirstNs.store(now);
    gFlag.store(true);
    return;
  }
  // A second signal terminates at once, unless it is the same signal delivered twice (timeout(1)
  // sends it to the process and then to its group) within kDuplicateNs.
  if (now - gFirstNs.load() >= kDuplicateNs) {
    ::signal(signal, SIG_DFL);
    raise(signal);
  }
}

}  // namespace

void installInterruptHandlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
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

}  // namespace firstshot
