#include "common/sampling/sampling.h"

#include <algorithm>

namespace firstshot {

namespace {
/// Unit vector from cos θ and φ about +z.
Vec3 sphericalDirection(float cosTheta, float phi) {
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
}  // namespace

Vec3 squareToUniformSphere(const Vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  return sphericalDirection(z, 2.0f * kPiF * u.y);
}

Vec3 squareToUniformHemisphere(const Vec2& u) { return sphericalDirection(u.x, 2.0f * kPiF * u.y); }

Vec3 squareToPhongLobe(const Vec2& u, float n) {
  // CDF of cos α under (n+1) cos^n α sin α dα is cos^{n+1} α, measured from the rim.
  const float cosAlpha = std::pow(u.x, 1.0f / (n + 1.0f));
  return sphericalDirection(cosAlpha, 2.0f * kPiF * u.y);
}

Vec3 squareToCosineHemisphereStratum(int j, int k, int M, int N, const Vec2& u) {
  // Projected solid angle is uniform in sin²θ: cell j covers sin²θ ∈ [j/M, (j+1)/M).
  const float sin2 = std::min(1.0f, (static_cast<float>(j) + u.x) / static_cast<float>(M));
  const float phi = 2.0f * kPiF * (static_cast<float>(k) + u.y) / static_cast<float>(N);
  const float sinTheta = std::sqrt(sin2);
  const float cosTheta = std::sqrt(std::max(0.0f, 1.0f - sin2));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

}  // namespace firstshot
