#pragma once
/// @file rng.h
/// Deterministic, counter-based random numbers. Every number is a pure function of a key and a
/// counter, so results never depend on thread scheduling or on how work is split between threads.
///
/// Exact keying (part of the output contract: changing it changes every image):
///   key  = hashKeys(seed, pixel, sampleIndex, stream), where
///          hashKeys(k0, k1, ..., km) = h_m with h_0 = mix(k0 ^ 0x6a09e667f3bcc909) and
///          h_i = mix(h_{i-1} ^ k_i) (mix = splitmix64 finaliser, Hasher::mix in common/hash.h);
///   x_d  = mix(key + (d + 1) * 0x9e3779b97f4a7c15)     for dimension d = 0, 1, 2, ...
///   u_d  = (x_d >> 40) * 2^-24                           (24 bits: an exact float in [0, 1)).
/// A Sampler walks d = 0, 1, 2, ... (one dimension per next1D, two per next2D); for a fixed key
/// this is exactly the splitmix64 sequence seeded with the key. The stream index separates
/// independent uses of the same (pixel, sample), e.g. camera path vs. light selection.
#include <cstdint>

#include "common/hash.h"
#include "common/math.h"

namespace fs {

namespace detail {
inline constexpr uint64_t kKeySalt = 0x6a09e667f3bcc909ull;  ///< first key word is xor-ed with this
inline constexpr uint64_t kWeyl = 0x9e3779b97f4a7c15ull;     ///< splitmix64 increment (golden ratio)

inline uint64_t hashKeysImpl(uint64_t h) { return h; }
template <typename... Rest>
inline uint64_t hashKeysImpl(uint64_t h, uint64_t k, Rest... rest) {
  return hashKeysImpl(Hasher::mix(h ^ k), static_cast<uint64_t>(rest)...);
}
}  // namespace detail

/// 64-bit hash of one or more integer keys (order matters). See the file comment for the formula.
template <typename... Keys>
inline uint64_t hashKeys(uint64_t first, Keys... rest) {
  return detail::hashKeysImpl(Hasher::mix(first ^ detail::kKeySalt), static_cast<uint64_t>(rest)...);
}

/// Maps 64 random bits to a float in [0, 1) using the top 24 bits (never returns 1.0f).
inline float bitsToUnitFloat(uint64_t x) { return static_cast<float>(x >> 40) * 0x1p-24f; }

/// Maps 64 random bits to a double in [0, 1) using the top 53 bits (never returns 1.0).
inline double bitsToUnitDouble(uint64_t x) { return static_cast<double>(x >> 11) * 0x1p-53; }

/// Stateless uniform number in [0, 1) from integer keys: bitsToUnitFloat(hashKeys(keys...)).
/// Use it where a single number is needed without carrying a Sampler (e.g. per-patch jitter).
template <typename... Keys>
inline float hashToUnit(uint64_t first, Keys... rest) {
  return bitsToUnitFloat(hashKeys(first, rest...));
}

/// Counter-based sampler: a small value type (16 bytes), cheap to create per pixel sample.
/// Copies continue independently from the same position (they produce the same numbers).
class Sampler {
 public:
  /// A sampler over key 0 (a placeholder to assign a keyed one to).
  Sampler() = default;
  /// Sampler for one (seed, pixel, sample index, stream); starts at dimension 0.
  Sampler(uint64_t seed, uint64_t pixel, uint64_t sampleIndex, uint64_t stream = 0)
      : key_(hashKeys(seed, pixel, sampleIndex, stream)) {}

  /// Sampler over an explicit key (e.g. from hashKeys with a different tuple).
  static Sampler fromKey(uint64_t key) { return Sampler(key); }

  /// 64 random bits of the current dimension; advances by one dimension.
  uint64_t nextBits() { return Hasher::mix(key_ + (++dim_) * detail::kWeyl); }
  /// Uniform float in [0, 1) (24-bit resolution, never 1.0f); advances by one dimension.
  float next1D() { return bitsToUnitFloat(nextBits()); }
  /// Two uniform floats in [0, 1)²; advances by two dimensions (x first).
  Vec2 next2D() {
    const float x = next1D();
    return {x, next1D()};
  }
  /// Uniform double in [0, 1) (53-bit resolution); advances by one dimension.
  double next1Dd() { return bitsToUnitDouble(nextBits()); }
  /// Uniform integer in [0, n) for n >= 1 (Lemire's multiply-shift; bias < n/2^32, negligible).
  uint32_t nextIndex(uint32_t n) {
    return static_cast<uint32_t>(((nextBits() >> 32) * static_cast<uint64_t>(n)) >> 32);
  }

  /// Index of the next dimension to be drawn.
  uint64_t dimension() const { return dim_; }
  /// Jumps to dimension @p d (e.g. to give each bounce a fixed block of dimensions).
  void setDimension(uint64_t d) { dim_ = d; }
  uint64_t key() const { return key_; }

 private:
  explicit Sampler(uint64_t key) : key_(key) {}
  uint64_t key_ = 0;
  uint64_t dim_ = 0;  ///< next dimension; x_d uses the counter value d + 1
};

}  // namespace fs
