#pragma once
/// @file hash.h
/// A small incremental 64-bit hash (FNV-1a over bytes, finished by a splitmix64 mix) for content
/// hashes and file checksums. Stable across platforms of the same endianness.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace firstshot {

class Hasher {
 public:
  Hasher& bytes(const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 0x100000001b3ull;
    return *this;
  }
  template <typename T>
  Hasher& add(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    return bytes(&v, sizeof(T));
  }
  Hasher& add(std::string_view s) {
    add<uint64_t>(s.size());
    return bytes(s.data(), s.size());
  }
  uint64_t value() const { return mix(h_); }

  /// splitmix64 finaliser: a good 64-bit mixer.
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace firstshot
