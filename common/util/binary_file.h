#pragma once
/// @file binary_file.h
/// The one frame of the project's binary files (the .fsd first-shot table, the irradiance cache's .fsic,
/// render checkpoints): writing and verifying reading. Little-endian throughout:
///   magic (8 bytes), version (u32), the format's own contents, checksum (u64: common/util/hash.h Hasher over
///   every byte before it), end marker (8 bytes).
/// Contents are plain values, strings (u32 length + bytes), arrays (their elements back to back) and,
/// where a format has them, tagged sections: a 4-byte tag, the section's length in bytes (u64), its
/// contents. Sections carry no version of their own: the file's version says which sections come, in which
/// order and layout, and a reader takes only the version it was built for. A file is written atomically (common/util/atomic_file.h: a temporary file, then a rename) and
/// read whole; the reader checks magic, version, end marker and checksum before any contents are read,
/// and every read is bounds-checked. Every failure is an InputError naming the file, the element at fault
/// (header, trailer, a section's tag or a format's field) and, for contents, the byte offset.
#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <fstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "common/util/atomic_file.h"
#include "common/util/hash.h"

namespace firstshot {

static_assert(std::endian::native == std::endian::little, "the binary files are little-endian");

/// What tells one binary format from another, and the words its errors use.
struct BinaryFormat {
  std::string_view magic;      ///< the first 8 bytes
  std::string_view endMarker;  ///< the last 8 bytes
  uint32_t version = 0;        ///< the u32 after the magic: the one version this build writes and reads
  /// The fixed header's bytes (magic and version included): a shorter file (trailer apart) is truncated.
  size_t headerBytes = 12;
  std::string_view noun;       ///< e.g. "first-shot file": "cannot open the …", "truncated …"
  std::string_view identity;   ///< e.g. "a first-shot (.fsd) file": "not … (wrong magic)"
  std::string_view remedy;     ///< what to do about a file this build cannot use, e.g. "run firstshot-preprocess again"
};

/// The checksum of a binary file's first @p n bytes (everything before the checksum itself).
inline uint64_t binaryChecksum(const void* data, size_t n) { return Hasher().bytes(data, n).value(); }

/// Writes a binary file's bytes: the header on construction, contents through put/str/array/sections,
/// the trailer in finish(). Bytes are kept in memory while a section is open (its length is filled in at
/// its end) and otherwise passed on to the stream in blocks, so a large array (a film's sums) is not copied.
class BinaryWriter {
 public:
  /// Writes @p format's magic and version to @p out.
  BinaryWriter(std::ostream& out, const BinaryFormat& format);

  /// One plain value, as its bytes in memory.
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof(T));
  }
  /// A string: u32 length, then its bytes.
  void str(std::string_view s) {
    put<uint32_t>(static_cast<uint32_t>(s.size()));
    bytes(s.data(), s.size());
  }
  /// A vector's elements back to back (its length is not written: the format says where that is).
  template <typename T>
  void array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(v.data(), v.size() * sizeof(T));
  }
  void bytes(const void* data, size_t n);

  /// Starts a section tagged @p tag (4 characters); sections do not nest.
  void beginSection(std::string_view tag);
  /// Ends the open section: fills in its length.
  void endSection();

  /// Writes the checksum and the end marker.
  void finish();

 private:
  void flush();
  std::ostream& out_;
  std::string_view endMarker_;
  Hasher hash_;
  std::vector<char> buf_;  ///< not yet written: the open section, or a block of plain values
  bool inSection_ = false;
};

/// Writes a binary file of @p format at @p path atomically (a temporary file beside it, then a rename):
/// the header, what @p contents writes, the trailer. If @p contents throws, nothing is written.
/// @p onInterrupt as writeAtomically. @throws std::runtime_error naming @p path on I/O failure.
void writeBinaryFile(const std::string& path, const BinaryFormat& format,
                     const std::function<void(BinaryWriter&)>& contents,
                     OnInterrupt onInterrupt = OnInterrupt::Discard);

/// Reads a binary file whole and checks its frame on construction, in this order: it opens, the magic,
/// the version, the end marker (with the size of header and trailer), the checksum. Then reads its
/// contents, between the header and the trailer, with bounds checks. Every failure throws InputError with
/// the file's path and the element named by the caller ("header", a section's tag, a field).
class BinaryReader {
 public:
  /// @throws InputError naming @p path: cannot open or read, wrong magic, another version, truncated
  ///         (end marker missing), checksum mismatch.
  BinaryReader(const std::string& path, const BinaryFormat& format);

  /// One plain value, as BinaryWriter::put wrote it; @p what names the element in errors (a section's tag, a field).
  template <typename T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    bytes(&v, sizeof(T), what);
    return v;
  }
  /// A string written by BinaryWriter::str (u32 length, then its bytes).
  std::string str(const char* what);
  /// @p n bytes into @p out.
  void bytes(void* out, size_t n, const char* what);
  /// @p count elements into @p v (resized), refused before any allocation when the contents hold fewer.
  template <typename T>
  void array(std::vector<T>& v, uint64_t count, const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (count > remaining() / sizeof(T))
      fail(what, "truncated or corrupt: " + std::to_string(count) + " elements of " + std::to_string(sizeof(T)) +
                     " bytes counted at offset " + std::to_string(pos_) + ", " + std::to_string(remaining()) +
                     " bytes left");
    v.resize(count);
    bytes(v.data(), count * sizeof(T), what);
  }

  /// Enters the section tagged @p tag (4 characters), which must come next; until leave(), reads stop at its end
  /// and remaining() counts what is left of it. Sections do not nest.
  void enter(const char* tag);
  /// Leaves the open section tagged @p tag, whose contents must have been read exactly.
  void leave(const char* tag);
  /// The contents must have been read exactly (nothing between them and the trailer).
  void expectEnd(const char* what);

  /// Bytes not yet read: of the open section, or else of the contents.
  uint64_t remaining() const { return end_ - pos_; }
  /// Offset in the file of the next byte to read.
  uint64_t offset() const { return pos_; }
  const std::string& path() const { return path_; }
  /// @throws InputError(path, what, message).
  [[noreturn]] void fail(const char* what, const std::string& message) const;

 private:
  std::string path_;
  std::vector<char> data_;
  uint64_t pos_ = 0;       ///< offset of the next byte to read
  uint64_t end_ = 0;       ///< where reads stop: the open section's end, or the trailer's first byte
  uint64_t outerEnd_ = 0;  ///< the trailer's first byte while a section is open
  bool inSection_ = false;
};

}  // namespace firstshot
