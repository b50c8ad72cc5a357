#pragma once
/// @file progress.h
/// A progress bar with ETA on stderr. Thread-safe: workers call advance(); it redraws at most every
/// 100 ms. Silent when quiet, or when stderr is not a terminal (unless forced).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace fs {

class Progress {
 public:
  Progress(std::string label, uint64_t total, bool quiet);
  ~Progress();
  /// Marks @p n more units done.
  void advance(uint64_t n = 1);
  /// Draws the final state and ends the line.
  void finish();
  /// Seconds since construction.
  double elapsed() const;

 private:
  void draw(bool final);
  std::string label_;
  uint64_t total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_, lastDraw_;
  std::mutex mutex_;
};

}  // namespace fs
