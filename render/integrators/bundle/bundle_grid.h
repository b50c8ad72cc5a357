#pragma once
/// @file bundle_grid.h
/// One bundle of parallel lines: B×B lines along a unit direction, on a square grid of spacing
/// h = 2R/B in the plane through the scene's bounding-sphere centre perpendicular to the
/// direction, shifted by one random offset in [0, h)² per bundle. Every point of that plane is then
/// met by a line with density exactly 1/δA⊥ (δA⊥ = h², the area per line), so a sum over the lines
/// hitting a surface, times δA⊥, is an unbiased estimate of the surface's projected area —
/// whatever the size of the surface. Lines outside the bounding disk are skipped (they meet nothing).
/// Also: the iteration's global direction, uniform on the sphere, random or low-discrepancy.
#include <cstdint>

#include "common/util/math.h"
#include "render/scene/ray.h"

namespace firstshot {

/// How the global directions ω_k are drawn.
enum class BundleDirections : uint8_t {
  Random,  ///< independent, uniform on the sphere, keyed by (seed, k)
  Halton,  ///< Halton points (bases 2, 3) of index k, rotated per seed (Cranley–Patterson), mapped to the sphere
};

/// Keys of the bundle's random numbers: hashKeys(seed, kBundleKey, iteration, stream, ...).
inline constexpr uint64_t kBundleKey = 0xb0d1e5ca77e2ull;

/// ω_k: uniform on the sphere (pdf 1/4π) for either sequence.
Vec3 bundleDirection(BundleDirections kind, uint64_t seed, uint64_t iteration);

class BundleGrid {
 public:
  /// @param direction unit direction of the lines; @param center, radius the bounding sphere (m);
  /// @param resolution B ≥ 1; @param offset the random shift in [0,1)² in units of the spacing.
  BundleGrid(const Vec3& direction, const Vec3& center, float radius, int resolution, const Vec2& offset);

  int resolution() const { return b_; }
  /// Area per line, δA⊥ = (2R/B)², m².
  float cellArea() const { return h_ * h_; }
  /// Line (a, b), 0 ≤ a, b < B, starting before the bounding sphere; false if it misses the sphere.
  bool line(int a, int b, Ray& ray) const;

 private:
  Frame frame_;
  Vec3 center_;
  float radius_, h_;
  int b_;
  Vec2 offset_;
};

}  // namespace firstshot
