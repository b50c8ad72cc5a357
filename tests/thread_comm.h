#pragma once
/// @file thread_comm.h
/// N ranks simulated by N threads of one process (common/util/comm.h), for tests of the rank-split code
/// paths without mpirun (so they also run under the sanitizers): runRanks(n, f) calls f(comm) on n
/// threads, each with the Comm of its rank; the exchanges meet at a barrier in call order.
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "common/util/comm.h"

namespace firstshot::test {

class ThreadRanks {
 public:
  explicit ThreadRanks(int n) : n_(n), slots_(size_t(n)) {}

  class RankComm final : public Comm {
   public:
    RankComm(ThreadRanks& all, int rank) : all_(all), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return all_.n_; }
    std::vector<Bytes> allGather(const Bytes& mine) override {
      bytesSent_ += mine.size() * uint64_t(all_.n_ - 1);
      return all_.exchange(rank_, mine);
    }
    std::vector<Bytes> gather(const Bytes& mine) override {
      if (rank_ != 0) bytesSent_ += mine.size();
      std::vector<Bytes> all = all_.exchange(rank_, mine);
      if (rank_ != 0) all.clear();
      return all;
    }
    void broadcast(Bytes& bytes) override {
      if (rank_ == 0) bytesSent_ += bytes.size() * uint64_t(all_.n_ - 1);
      bytes = all_.exchange(rank_, bytes)[0];
    }
    bool any(bool flag) override {
      for (const Bytes& b : all_.exchange(rank_, Bytes{uint8_t(flag)}))
        if (b[0]) return true;
      return false;
    }
    uint64_t sum(uint64_t value) override {
      ByteWriter w;
      w.put(value);
      uint64_t total = 0;
      for (const Bytes& b : all_.exchange(rank_, w.bytes())) total += ByteReader(b).get<uint64_t>();
      return total;
    }
    [[noreturn]] void abort(int code) override { throw std::runtime_error("rank aborted with code " + std::to_string(code)); }

   private:
    ThreadRanks& all_;
    int rank_;
  };

  /// Runs @p body on every rank (one thread each) and waits; rethrows the first exception.
  void run(const std::function<void(Comm&)>& body) {
    std::vector<std::thread> threads;
    std::exception_ptr error;
    std::mutex errorMutex;
    for (int r = 0; r < n_; ++r)
      threads.emplace_back([&, r] {
        RankComm comm(*this, r);
        try {
          body(comm);
        } catch (...) {
          {
            std::lock_guard lock(errorMutex);
            if (!error) error = std::current_exception();
          }
          std::lock_guard lock(mutex_);  // the other ranks stop at their next exchange
          failed_ = true;
          cv_.notify_all();
        }
      });
    for (auto& t : threads) t.join();
    if (error) std::rethrow_exception(error);
  }

 private:
  /// Every rank's bytes to every rank: deposit, wait for all, copy, wait until all have copied.
  std::vector<Bytes> exchange(int rank, const Bytes& mine) {
    std::unique_lock lock(mutex_);
    auto failed = [&] {
      if (failed_) throw std::runtime_error("another rank failed");
    };
    cv_.wait(lock, [&] { return !draining_ || failed_; });
    failed();
    slots_[size_t(rank)] = mine;
    if (++arrived_ == n_) {
      draining_ = true;
      cv_.notify_all();
    } else {
      cv_.wait(lock, [&] { return draining_ || failed_; });
      failed();
    }
    std::vector<Bytes> all = slots_;
    if (--arrived_ == 0) {
      draining_ = false;
      cv_.notify_all();
    }
    return all;
  }

  int n_;
  std::vector<Bytes> slots_;
  std::mutex mutex_;
  std::condition_variable cv_;
  int arrived_ = 0;
  bool draining_ = false;
  bool failed_ = false;
};

/// Calls @p body(comm) on @p ranks simulated ranks (threads) and waits for all.
inline void runRanks(int ranks, const std::function<void(Comm&)>& body) { ThreadRanks(ranks).run(body); }

}  // namespace firstshot::test
