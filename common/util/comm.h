#pragma once
/// @file comm.h
/// The processes of one run as the tools see them: an MPI job's ranks (common/mpi/mpi_comm.h, the
/// `-mpi` executables) or a single process (serialComm()). Work is split by rank and the results
/// are exchanged as bytes in a fixed order, so that every output is bit-identical for any number of
/// ranks (docs/mpi.md). Every exchange is collective: all ranks call it, in the same order.
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace firstshot {

using Bytes = std::vector<uint8_t>;

class Comm {
 public:
  virtual ~Comm() = default;
  /// This process's rank, 0 .. size() − 1.
  virtual int rank() const = 0;
  /// Processes in the run (1 without MPI).
  virtual int size() const = 0;
  /// Rank 0 writes the outputs, shows progress and prints the results.
  bool root() const { return rank() == 0; }
  /// The rank that item @p index of a work list belongs to: items are dealt round-robin.
  int owner(uint64_t index) const { return int(index % uint64_t(size())); }
  /// True if item @p index of a work list belongs to this rank.
  bool mine(uint64_t index) const { return owner(index) == rank(); }

  /// Every rank's @p mine, indexed by rank, on every rank.
  virtual std::vector<Bytes> allGather(const Bytes& mine) = 0;
  /// Every rank's @p mine, indexed by rank, on rank 0; an empty list on the other ranks.
  virtual std::vector<Bytes> gather(const Bytes& mine) = 0;
  /// Rank 0's @p bytes on every rank (replacing theirs).
  virtual void broadcast(Bytes& bytes) = 0;
  /// True on every rank if @p flag is true on any rank.
  virtual bool any(bool flag) = 0;
  /// The sum over ranks of @p value, on every rank.
  virtual uint64_t sum(uint64_t value) = 0;
  /// Stops every rank of the run with exit code @p code (after this rank's message is printed).
  [[noreturn]] virtual void abort(int code) = 0;

  /// Bytes this rank has sent to other ranks so far (for the reports of docs/mpi.md).
  uint64_t bytesSent() const { return bytesSent_; }

 protected:
  uint64_t bytesSent_ = 0;
};

/// The run of one process (rank 0 of 1): the exchanges return the process's own data.
Comm& serialComm();

/// Appends plain values to a byte buffer, to be read back in the same order by ByteReader.
class ByteWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &value, sizeof(T));
  }
  /// The element count (uint64) and then the elements.
  template <class T>
  void putVector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<uint64_t>(values.size());
    const size_t at = bytes_.size();
    bytes_.resize(at + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(bytes_.data() + at, values.data(), values.size() * sizeof(T));
  }
  Bytes& bytes() { return bytes_; }

 private:
  Bytes bytes_;
};

/// Reads what a ByteWriter wrote. @throws std::runtime_error past the end (a corrupt exchange).
class ByteReader {
 public:
  explicit ByteReader(const Bytes& bytes) : bytes_(bytes) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> getVector() {
    const uint64_t n = get<uint64_t>();
    if (n > (bytes_.size() - at_) / sizeof(T)) fail();
    std::vector<T> values(n);
    if (n) std::memcpy(values.data(), take(n * sizeof(T)), n * sizeof(T));
    return values;
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  const uint8_t* take(size_t n) {
    if (n > bytes_.size() - at_) fail();
    const uint8_t* p = bytes_.data() + at_;
    at_ += n;
    return p;
  }
  [[noreturn]] static void fail();
  const Bytes& bytes_;
  size_t at_ = 0;
};

}  // namespace firstshot
