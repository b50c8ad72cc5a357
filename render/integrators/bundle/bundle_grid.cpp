// Bundle directions and line grids.
#include "render/integrators/bundle/bundle_grid.h"

#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"

namespace firstshot {

namespace {

/// Radical inverse of @p i in base @p base, in [0, 1).
double radicalInverse(uint64_t i, uint64_t base) {
  double inv = 1.0 / double(base), f = inv, r = 0.0;
  for (; i > 0; i /= base, f *= inv) r += f * double(i % base);
  return r;
}

}  // namespace

Vec3 bundleDirection(BundleDirections kind, uint64_t seed, uint64_t iteration) {
  Vec2 u;
  if (kind == BundleDirections::Random) {
    u = Vec2(hashToUnit(seed, kBundleKey, iteration, 0, 0), hashToUnit(seed, kBundleKey, iteration, 0, 1));
  } else {
    const double ru = bitsToUnitDouble(hashKeys(seed, kBundleKey, 0, 0)), rv = bitsToUnitDouble(hashKeys(seed, kBundleKey, 0, 1));
    double x = radicalInverse(iteration, 2) + ru, y = radicalInverse(iteration, 3) + rv;
    x -= std::floor(x), y -= std::floor(y);
    u = Vec2(std::min(float(x), 0x1.fffffep-1f), std::min(float(y), 0x1.fffffep-1f));
  }
  return glm::normalize(squareToUniformSphere(u));
}

BundleGrid::BundleGrid(const Vec3& direction, const Vec3& center, float radius, int resolution, const Vec2& offset)
    : frame_(direction), center_(center), radius_(radius), h_(2.0f * radius / float(resolution)), b_(resolution),
      offset_(offset) {}

bool BundleGrid::line(int a, int b, Ray& ray) const {
  const float s = -radius_ + (float(a) + offset_.x) * h_, t = -radius_ + (float(b) + offset_.y) * h_;
  if (s * s + t * t > radius_ * radius_) return false;
  const float back = 1.01f * radius_;
  ray = Ray(center_ + s * frame_.s + t * frame_.t - back * frame_.n, frame_.n, 0.0f, 2.0f * back);
  return true;
}

}  // namespace firstshot
