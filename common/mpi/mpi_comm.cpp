// MPI_COMM_WORLD behind the Comm interface: byte exchanges in rank order, in pieces of at most
// 1 GiB (MPI counts are int).
#include "common/mpi/mpi_comm.h"

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace firstshot {

namespace {

constexpr uint64_t kPiece = uint64_t(1) << 30;

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

/// Broadcasts @p bytes (whose size every rank already knows) from @p root, piece by piece.
void bcastBytes(Bytes& bytes, int root) {
  for (uint64_t at = 0; at < bytes.size(); at += kPiece) {
    const int n = int(std::min<uint64_t>(kPiece, bytes.size() - at));
    check(MPI_Bcast(bytes.data() + at, n, MPI_BYTE, root, MPI_COMM_WORLD), "MPI_Bcast");
  }
}

class MpiComm final : public Comm {
 public:
  MpiComm() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  std::vector<Bytes> allGather(const Bytes& mine) override {
    std::vector<uint64_t> sizes(static_cast<size_t>(size_), 0);
    const uint64_t n = mine.size();
    check(MPI_Allgather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD), "MPI_Allgather");
    std::vector<Bytes> all(static_cast<size_t>(size_));
    for (int r = 0; r < size_; ++r) {
      Bytes& b = all[size_t(r)];
      if (r == rank_) b = mine;
      else b.resize(sizes[size_t(r)]);
      bcastBytes(b, r);
    }
    bytesSent_ += n * uint64_t(size_ - 1);
    return all;
  }

  std::vector<Bytes> gather(const Bytes& mine) override {
    std::vector<Bytes> all;
    if (rank_ != 0) {
      const uint64_t n = mine.size();
      check(MPI_Send(&n, 1, MPI_UINT64_T, 0, 0, MPI_COMM_WORLD), "MPI_Send");
      for (uint64_t at = 0; at < n; at += kPiece)
        check(MPI_Send(mine.data() + at, int(std::min(kPiece, n - at)), MPI_BYTE, 0, 1, MPI_COMM_WORLD), "MPI_Send");
      bytesSent_ += n;
      return all;
    }
    all.resize(size_t(size_));
    all[0] = mine;
    for (int r = 1; r < size_; ++r) {
      uint64_t n = 0;
      check(MPI_Recv(&n, 1, MPI_UINT64_T, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
      Bytes& b = all[size_t(r)];
      b.resize(n);
      for (uint64_t at = 0; at < n; at += kPiece)
        check(MPI_Recv(b.data() + at, int(std::min(kPiece, n - at)), MPI_BYTE, r, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "MPI_Recv");
    }
    return all;
  }

  void broadcast(Bytes& bytes) override {
    uint64_t n = bytes.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast");
    if (rank_ != 0) bytes.resize(n);
    else bytesSent_ += n * uint64_t(size_ - 1);
    bcastBytes(bytes, 0);
  }

  bool any(bool flag) override {
    int in = flag ? 1 : 0, out = 0;
    check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD), "MPI_Allreduce");
    return out != 0;
  }

  uint64_t sum(uint64_t value) override {
    uint64_t out = 0;
    check(MPI_Allreduce(&value, &out, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }

  [[noreturn]] void abort(int code) override {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);  // not reached
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  int provided = 0;
  if (MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) {
    std::fprintf(stderr, "%s: error: MPI_Init_thread failed\n", argc > 0 ? argv[0] : "firstshot");
    std::exit(1);
  }
  if (provided < MPI_THREAD_SERIALIZED) {
    std::fprintf(stderr, "%s: error: the MPI library does not support MPI_THREAD_SERIALIZED\n", argv[0]);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  comm_ = std::make_unique<MpiComm>();
}

MpiSession::~MpiSession() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

Comm& MpiSession::comm() { return *comm_; }

}  // namespace firstshot
