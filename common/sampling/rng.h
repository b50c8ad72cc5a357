#pragma once
/// @file rng.h
/// Deterministic, counter-based random numbers. Every number is a pure function of a key and a
/// counter, so results never depend on thread scheduling or on how work is split between threads.
///
/// Exact keying (part of the output contract: changing it changes every image):
///   key  = hashKeys(seed, pixel, sampleIndex, stream), where
///          hashKeys(k0, k1, ..., km) = h_m with h_0 = mix(k0 ^ 0x6a09e667f3bcc909) and
///          h_i = mix(h_{i-1} ^ k_i) (mix = splitmix64 finaliser, Hasher::mix in common/util/hash.h);
///   x_d  = mix(key + (d + 1) * 0x9e3779b97f4a7c15)     for dimension d = 0, 1, 2, ...
///   u_d  = (x_d >> 40) * 2^-24                           (24 bits: an exact float in [0, 1)).
/// A Sampler walks d = 0, 1, 2, ... (one dimension per next1D, two per next2D); for a fixed key
/// this is exactly the splitmix64 sequence seeded with the key. The stream index separates
/// independent uses of the same (pixel, sample), e.g. camera path vs. light selection.
///
/// Sobol' mode (SamplerMode::Sobol, Sampler::sobol; firstshot-render --sampler sobol): the same
/// contract — the numbers of dimension d of sample i of pixel p with seed s depend on (s, p, i, d,
/// stream) and on whether d is drawn by next1D or as the first dimension of a next2D, nothing
/// else — but the samples of one pixel are stratified against each other (Burley 2020, "Practical
/// Hash-based Owen Scrambling"):
///   pk     = hashKeys(seed, pixel, stream, kSobolSalt)                      (per pixel, no index)
///   h      = mix(pk + (d + 1) * 0x9e3779b97f4a7c15), h' = mix(h)           (per pixel and dimension)
///   j      = owen(i mod 2^32, low32(h))             the shuffled sample index (nested scramble of i)
///   next2D at d: (owen(vdc(j), high32(h)), owen(sobol1(j), low32(h')))     consumes d, d + 1
///   next1D at d:  owen(vdc(j), high32(h))                                   consumes d
/// where vdc is bit reversal (Sobol' dimension 0), sobol1 the Sobol' second dimension (direction
/// numbers v_0 = 2^31, v_{k+1} = v_k ^ (v_k >> 1)) and owen(x, seed) a hash-based nested uniform
/// scramble: x's bits reversed, a bijection in which every bit depends only on the bits below it
/// (prefixHash), reversed back — so each digit is flipped by a function of the digits above it.
/// Together (vdc, sobol1) is a (0,2)-sequence: every aligned block of 2^k indices is a (0,k,2)-net
/// (one point per elementary interval of area 2^-k), the scrambles keep that, and the shuffle maps
/// the indices [0, 2^k) onto one aligned block: the first 2^k samples of a pixel are stratified
/// in every pair of dimensions drawn by next2D (and in every 1D dimension). Pairs from different
/// start dimensions are scrambled independently (a pair's key is its first dimension, so the
/// callers' setDimension jumps need no alignment). Floats keep the top 24 of the 32 bits;
/// nextIndex(n) is floor(n · u) of next1D's 32 bits u / 2^32; next1Dd takes those 32 bits and then
/// the top 21 of h' (random below the stratification).
/// nextBits stays random in this mode (it derives keys): mix(hashKeys(pk, i) + (d + 1) * kWeyl).
#include <cstdint>
#include <utility>

#include "common/util/hash.h"
#include "common/util/math.h"

namespace firstshot {

namespace detail {
inline constexpr uint64_t kKeySalt = 0x6a09e667f3bcc909ull;  ///< first key word is xor-ed with this
inline constexpr uint64_t kWeyl = 0x9e3779b97f4a7c15ull;     ///< splitmix64 increment (golden ratio)
inline constexpr uint64_t kSobolSalt = 0x536f626f6c273230ull; ///< last key word of a Sobol'-mode pixel key

/// Reverses the 32 bits of @p x (bit 0 <-> bit 31).
inline uint32_t reverseBits32(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  return __builtin_bswap32(x);
}

/// A seeded bijection of 32-bit words in which output bit k depends only on input bits 0..k (each
/// step has that property: adding, multiplying by an odd number, x ^= x * even). On bit-reversed
/// numbers it is a nested scramble: a digit's flip depends on the more significant digits only.
inline uint32_t prefixHash(uint32_t x, uint32_t seed) {
  x ^= x * 0x5c3a96b2u;
  x += seed;
  x *= (seed >> 15) | 1u;
  x ^= x * 0x2d7e4f18u;
  x += seed * 0x9e3779b9u;
  x ^= x * 0xa3b1c6d4u;
  x *= 0x7f4a7c15u | 1u;
  x ^= x * 0x34e5a9f6u;
  return x;
}

/// Hash-based Owen (nested uniform) scramble of the base-2 fraction x / 2^32.
inline uint32_t owenScramble(uint32_t x, uint32_t seed) { return reverseBits32(prefixHash(reverseBits32(x), seed)); }

/// The second dimension of the Sobol' sequence (sobolSecond): x = XOR over the set bits k of i of v_k, with
/// v_0 = 2^31 and v_{k+1} = v_k ^ (v_k >> 1), i.e. v_k's bit 31 − r is binom(k, r) mod 2 (Pascal's
/// triangle), which is 1 iff r's bits are a subset of k's (Lucas). So bit 31 − r of x is the XOR of
/// i's bits k ⊇ r: a superset-XOR transform over the five bits of the position, one shift, mask and
/// XOR per position bit, then reversed. (tests/test_sampler.cpp checks it against the recurrence.)
/// This is reverseBits32(sobolSecond(i)), the form the scramble takes.
inline uint32_t sobolSecondReversed(uint32_t i) {
  i ^= (i >> 1) & 0x55555555u;
  i ^= (i >> 2) & 0x33333333u;
  i ^= (i >> 4) & 0x0f0f0f0fu;
  i ^= (i >> 8) & 0x00ff00ffu;
  i ^= (i >> 16) & 0x0000ffffu;
  return i;
}
inline uint32_t sobolSecond(uint32_t i) { return reverseBits32(sobolSecondReversed(i)); }

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

/// How a Sampler draws its numbers (see the file comment).
enum class SamplerMode : uint32_t {
  Independent,  ///< every (key, dimension) an independent hash: today's images
  Sobol,        ///< per pixel, Owen-scrambled and shuffled Sobol' pairs (stratified over the sample index)
};

/// Counter-based sampler: a small value type (24 bytes), cheap to create per pixel sample.
/// Copies continue independently from the same position (they produce the same numbers).
class Sampler {
 public:
  /// A sampler over key 0 (a placeholder to assign a keyed one to).
  Sampler() = default;
  /// Sampler for one (seed, pixel, sample index, stream); starts at dimension 0. Independent mode.
  Sampler(uint64_t seed, uint64_t pixel, uint64_t sampleIndex, uint64_t stream = 0)
      : key_(hashKeys(seed, pixel, sampleIndex, stream)) {}

  /// Sampler in Sobol' mode for one (seed, pixel, sample index, stream): the samples i = 0, 1, ...
  /// of one (seed, pixel, stream) are stratified (file comment). Only the low 32 bits of the index count.
  static Sampler sobol(uint64_t seed, uint64_t pixel, uint64_t sampleIndex, uint64_t stream = 0) {
    Sampler s(hashKeys(seed, pixel, stream, detail::kSobolSalt));
    s.index_ = detail::reverseBits32(static_cast<uint32_t>(sampleIndex));
    s.mode_ = SamplerMode::Sobol;
    return s;
  }
  /// Sampler(seed, pixel, sampleIndex, stream) or sobol(...), as @p mode says.
  static Sampler make(SamplerMode mode, uint64_t seed, uint64_t pixel, uint64_t sampleIndex, uint64_t stream = 0) {
    return mode == SamplerMode::Sobol ? sobol(seed, pixel, sampleIndex, stream) : Sampler(seed, pixel, sampleIndex, stream);
  }

  /// Sampler over an explicit key (e.g. from hashKeys with a different tuple). Independent mode.
  static Sampler fromKey(uint64_t key) { return Sampler(key); }

  /// 64 random bits of the current dimension; advances by one dimension. Random (not stratified)
  /// in both modes: meant for keys of other samplers.
  uint64_t nextBits() {
    const uint64_t key = mode_ == SamplerMode::Sobol ? hashKeys(key_, detail::reverseBits32(index_)) : key_;
    return Hasher::mix(key + (++dim_) * detail::kWeyl);
  }
  /// Uniform float in [0, 1) (24-bit resolution, never 1.0f); advances by one dimension.
  float next1D() {
    if (mode_ == SamplerMode::Sobol) return static_cast<float>(sobol1D() >> 8) * 0x1p-24f;
    return bitsToUnitFloat(nextBits());
  }
  /// Two uniform floats in [0, 1)²; advances by two dimensions (x first).
  Vec2 next2D() {
    if (mode_ == SamplerMode::Sobol) {
      uint64_t h;
      const auto [x, y] = sobolPair(h);
      return {static_cast<float>(x >> 8) * 0x1p-24f, static_cast<float>(y >> 8) * 0x1p-24f};
    }
    const float x = next1D();
    return {x, next1D()};
  }
  /// next2D() with x a double of 53 bits (Sobol' mode: the pair's 32 stratified bits, then 21 random
  /// ones), for a choice among many items by a CDF whose remainder is used again (x) and a float y.
  Vec2d next2Dd() {
    if (mode_ == SamplerMode::Sobol) {
      uint64_t h;
      const auto [x, y] = sobolPair(h);
      const uint64_t low = Hasher::mix(h + detail::kWeyl) >> 43;
      return {static_cast<double>((uint64_t(x) << 21) | low) * 0x1p-53, static_cast<double>(y >> 8) * 0x1p-24};
    }
    const double x = next1Dd();
    return {x, double(next1D())};
  }
  /// Uniform double in [0, 1) (53-bit resolution); advances by one dimension. Sobol' mode: the
  /// 32 stratified bits, then 21 random ones.
  double next1Dd() {
    if (mode_ == SamplerMode::Sobol) {
      const uint64_t low = Hasher::mix(dimensionHash(dim_)) >> 43;  // before sobol1D advances
      return static_cast<double>((uint64_t(sobol1D()) << 21) | low) * 0x1p-53;
    }
    return bitsToUnitDouble(nextBits());
  }
  /// Uniform integer in [0, n) for n >= 1 (Lemire's multiply-shift; bias < n/2^32, negligible).
  uint32_t nextIndex(uint32_t n) {
    const uint64_t u = mode_ == SamplerMode::Sobol ? uint64_t(sobol1D()) : (nextBits() >> 32);
    return static_cast<uint32_t>((u * static_cast<uint64_t>(n)) >> 32);
  }

  /// Index of the next dimension to be drawn.
  uint64_t dimension() const { return dim_; }
  /// Jumps to dimension @p d (e.g. to give each bounce a fixed block of dimensions).
  void setDimension(uint64_t d) { dim_ = d; }
  /// Independent mode: the key of the numbers; Sobol' mode: the pixel's key (without the index).
  uint64_t key() const { return key_; }
  SamplerMode mode() const { return mode_; }

 private:
  /// The Owen-scrambled Sobol' pair of the current dimension, 32 bits each; advances by two
  /// dimensions and sets @p h to the pair's dimension hash.
  std::pair<uint32_t, uint32_t> sobolPair(uint64_t& h) {
    // owen(vdc(j)) = reverse(prefixHash(j)) and owen(sobol1(j)) = reverse(prefixHash(reverse(sobol1(j)))),
    // with j = reverse(prefixHash(reverse(i))): the file comment's formula with fewer reversals.
    h = dimensionHash(dim_);
    const uint64_t h2 = Hasher::mix(h);
    dim_ += 2;
    const uint32_t j = shuffledIndex(h);
    const uint32_t x = detail::reverseBits32(detail::prefixHash(j, static_cast<uint32_t>(h >> 32)));
    const uint32_t y = detail::reverseBits32(
        detail::prefixHash(detail::sobolSecondReversed(j), static_cast<uint32_t>(h2)));
    return {x, y};
  }
  explicit Sampler(uint64_t key) : key_(key) {}
  /// Sobol' mode: the hash of (pixel key, dimension d) that seeds d's shuffle and scrambles.
  uint64_t dimensionHash(uint64_t d) const { return Hasher::mix(key_ + (d + 1) * detail::kWeyl); }
  /// Sobol' mode: 32 bits of the scrambled van der Corput point of the current dimension; advances.
  uint32_t sobol1D() {
    const uint64_t h = dimensionHash(dim_++);
    return detail::reverseBits32(detail::prefixHash(shuffledIndex(h), static_cast<uint32_t>(h >> 32)));
  }
  /// Sobol' mode: the shuffled index j = owen(i, low32(h)) of the file comment (index_ is i reversed).
  uint32_t shuffledIndex(uint64_t h) const {
    return detail::reverseBits32(detail::prefixHash(index_, static_cast<uint32_t>(h)));
  }

  uint64_t key_ = 0;
  uint64_t dim_ = 0;  ///< next dimension; x_d uses the counter value d + 1
  uint32_t index_ = 0;  ///< Sobol' mode: the sample index's low 32 bits, reversed
  SamplerMode mode_ = SamplerMode::Independent;
};

/// The position of a camera sample in its pixel: @p sampler's next two dimensions, made for (@p seed, @p pixel,
/// @p index, @p stream) in @p mode; where @p jitterSeed differs from @p seed, those of the sampler of (@p jitterSeed,
/// @p pixel, @p index, @p stream) instead, @p sampler skipping its own (the integrator pilot's two images of two seeds
/// then sample the same positions, and the edges' aliasing, which the render's stratified samples nearly remove,
/// cancels in their difference).
inline Vec2 cameraJitter(Sampler& sampler, SamplerMode mode, uint64_t seed, uint64_t jitterSeed, uint64_t pixel,
                         uint64_t index, uint64_t stream = 0) {
  if (jitterSeed == seed) return sampler.next2D();
  Sampler own = Sampler::make(mode, jitterSeed, pixel, index, stream);
  sampler.setDimension(sampler.dimension() + 2);
  return own.next2D();
}

}  // namespace firstshot
