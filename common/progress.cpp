#include "common/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace fs {

Progress::Progress(std::string label, uint64_t total, bool quiet)
    : label_(std::move(label)), total_(total), start_(std::chrono::steady_clock::now()), lastDraw_(start_) {
  const char* force = std::getenv("FIRSTSHOT_PROGRESS");
  enabled_ = !quiet && (isatty(STDERR_FILENO) || (force && *force == '1'));
}

Progress::~Progress() { finish(); }

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::advance(uint64_t n) {
  done_ += n;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = now;
  draw(false);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  draw(true);
}

void Progress::draw(bool final) {
  const uint64_t done = std::min(done_.load(), total_);
  const double frac = total_ ? double(done) / double(total_) : 1.0;
  const double t = elapsed();
  const int width = 30;
  std::string bar(size_t(frac * width), '#');
  bar.resize(width, '-');
  char eta[32] = "";
  if (!final && frac > 0) std::snprintf(eta, sizeof eta, " ETA %.1fs", t / frac - t);
  std::fprintf(stderr, "\r%s [%s] %5.1f%% %llu/%llu %.1fs%s   %s", label_.c_str(), bar.c_str(), 100 * frac,
               (unsigned long long)done, (unsigned long long)total_, t, eta, final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace fs
