#pragma once
/// @file progress.h
/// Progress of a long stage on stderr, for a person at a terminal and for a log alike. Thread-safe:
/// workers call advance(); a ticker thread of the Progress draws.
///
/// - stderr a terminal (or FIRSTSHOT_PROGRESS=1): a bar with percentage, done/total, elapsed time and
///   ETA, redrawn in place every 100 ms ('\r'), ended by a newline when the stage finishes.
/// - stderr not a terminal (a pipe, a file, a CI log, an MPI launcher): plain lines, no '\r' and no
///   ANSI codes — one when the stage starts, one every FIRSTSHOT_PROGRESS_INTERVAL seconds (default 5)
///   with label, percentage, done/total, elapsed time and ETA, and one with the stage's total time.
/// - quiet (the tools' --quiet, every rank but 0 of an MPI run): nothing.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace firstshot {

class Progress {
 public:
  /// A stage of @p total units (light samples, camera samples, fill tasks …), counted by advance().
  Progress(std::string label, uint64_t total, bool quiet);
  /// A stage bounded by a time limit of @p seconds (> 0): its fraction done is the elapsed time over
  /// the limit (capped at 1), so the caller need not call advance(). (The class cannot be moved; the
  /// result is constructed in place.)
  static Progress timed(std::string label, double seconds, bool quiet);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Marks @p n more units done (no effect on a timed stage).
  void advance(uint64_t n = 1);
  /// Draws the final state (terminal) or the closing line with the stage's total time (lines). A
  /// stage ended before all its units, by an error or an interruption, says where it stopped.
  void finish();
  /// Seconds since construction.
  double elapsed() const;

  /// Seconds between two lines when stderr is not a terminal: FIRSTSHOT_PROGRESS_INTERVAL if set,
  /// else 5. @throws InputError when it is set but not a positive number.
  static double lineInterval();

 private:
  enum class Mode { Off, Bar, Lines };
  Progress(std::string label, uint64_t total, double budgetSeconds, bool quiet);
  /// Done units, capped at the total (a timed stage: elapsed milliseconds).
  uint64_t done() const;
  /// "12.3/40.0 s" (timed) or "123/456".
  std::string count(uint64_t done) const;
  void tick();
  void drawBar(bool final);
  void drawLine(bool final);
  void drawStart();

  std::string label_;
  uint64_t total_;             ///< units, or the time limit in milliseconds when timed_
  bool timed_;
  Mode mode_ = Mode::Off;
  std::chrono::duration<double> interval_{0.1};  ///< between two draws
  std::atomic<uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;           ///< guards finished_ and the drawing
  std::condition_variable wake_;
  bool finished_ = false;
  std::thread ticker_;
};

}  // namespace firstshot
