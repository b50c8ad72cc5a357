#include "common/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <fmt/core.h>

#include "common/util/error.h"

namespace firstshot {

namespace {

constexpr double kDefaultLineInterval = 5.0;  ///< seconds between two lines in a log
constexpr double kBarInterval = 0.1;          ///< seconds between two redraws of the bar

void print(const std::string& text) {
  std::fputs(text.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace

double Progress::lineInterval() {
  const char* text = std::getenv("FIRSTSHOT_PROGRESS_INTERVAL");
  if (!text || !*text) return kDefaultLineInterval;
  char* end = nullptr;
  errno = 0;
  const double s = std::strtod(text, &end);
  if (errno != 0 || *end != '\0' || !std::isfinite(s) || !(s > 0))
    throw InputError("", "FIRSTSHOT_PROGRESS_INTERVAL",
                     fmt::format("\"{}\" is not a positive number of seconds", text));
  return s;
}

Progress::Progress(std::string label, uint64_t total, bool quiet) : Progress(std::move(label), total, 0.0, quiet) {}

Progress Progress::timed(std::string label, double seconds, bool quiet) {
  return Progress(std::move(label), 0, std::max(seconds, 1e-3), quiet);
}

Progress::Progress(std::string label, uint64_t total, double budgetSeconds, bool quiet)
    : label_(std::move(label)),
      total_(budgetSeconds > 0 ? uint64_t(std::llround(budgetSeconds * 1000.0)) : total),
      timed_(budgetSeconds > 0),
      start_(std::chrono::steady_clock::now()) {
  if (quiet) return;
  const char* force = std::getenv("FIRSTSHOT_PROGRESS");
  const bool bar = isatty(STDERR_FILENO) || (force && std::string(force) == "1");
  mode_ = bar ? Mode::Bar : Mode::Lines;
  interval_ = std::chrono::duration<double>(bar ? kBarInterval : lineInterval());
  if (mode_ == Mode::Lines) drawStart();
  ticker_ = std::thread([this] { tick(); });
}

Progress::~Progress() {
  try {
    finish();
  } catch (...) {  // a destructor does not throw; the drawing is all that is lost
  }
}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::advance(uint64_t n) {
  if (!timed_) done_.fetch_add(n, std::memory_order_relaxed);
}

uint64_t Progress::done() const {
  if (timed_) return std::min(total_, uint64_t(elapsed() * 1000.0));
  return std::min(done_.load(std::memory_order_relaxed), total_);
}

std::string Progress::count(uint64_t done) const {
  if (timed_) return fmt::format("{:.1f}/{:.1f} s", double(done) / 1000.0, double(total_) / 1000.0);
  return fmt::format("{}/{}", done, total_);
}

void Progress::tick() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, interval_, [this] { return finished_; })) {
    if (mode_ == Mode::Bar)
      drawBar(false);
    else
      drawLine(false);
  }
}

void Progress::finish() {
  {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
  }
  if (mode_ == Mode::Off) return;
  wake_.notify_all();
  ticker_.join();
  std::lock_guard lock(mutex_);
  if (mode_ == Mode::Bar)
    drawBar(true);
  else
    drawLine(true);
}

void Progress::drawStart() {
  print(timed_ ? fmt::format("{}: started, time limit {:.1f} s\n", label_, double(total_) / 1000.0)
               : fmt::format("{}: started, {} to do\n", label_, total_));
}

void Progress::drawBar(bool final) {
  const uint64_t done = this->done();
  const double frac = total_ ? double(done) / double(total_) : 1.0;
  const double t = elapsed();
  const int width = 30;
  std::string bar(size_t(frac * width), '#');
  bar.resize(width, '-');
  const std::string eta = !final && frac > 0 ? fmt::format(" ETA {:.1f}s", t / frac - t) : std::string();
  print(fmt::format("\r{} [{}] {:5.1f}% {} {:.1f}s{}   {}", label_, bar, 100 * frac, count(done), t, eta,
                    final ? "\n" : ""));
}

void Progress::drawLine(bool final) {
  const uint64_t done = this->done();
  const double frac = total_ ? double(done) / double(total_) : 1.0;
  const double t = elapsed();
  if (final && (done >= total_ || timed_))
    print(fmt::format("{}: done in {:.2f} s ({})\n", label_, t, count(done)));
  else if (final)
    print(fmt::format("{}: stopped at {:.1f}% ({}) after {:.2f} s\n", label_, 100 * frac, count(done), t));
  else
    print(fmt::format("{}: {:.1f}% ({}), {:.1f} s elapsed, ETA {}\n", label_, 100 * frac, count(done), t,
                      frac > 0 ? fmt::format("{:.1f} s", t / frac - t) : std::string("unknown")));
}

}  // namespace firstshot
