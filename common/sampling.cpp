#include "common/sampling.h"

#include <algorithm>

namespace fs {

namespace {
/// Unit vector from cos θ and φ about +z.
Vec3 sphericalDirection(float cosTheta, float phi) {
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
}  // namespace

Vec2 squareToUniformDiskConcentric(const Vec2& u) {
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = 0.25f * kPiF * (b / a);
  } else {
    r = b;
    phi = 0.5f * kPiF - 0.25f * kPiF * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

Vec3 squareToUniformSphere(const Vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  return sphericalDirection(z, 2.0f * kPiF * u.y);
}

Vec3 squareToUniformHemisphere(const Vec2& u) { return sphericalDirection(u.x, 2.0f * kPiF * u.y); }

Vec3 squareToCosineHemisphere(const Vec2& u) {
  const Vec2 d = squareToUniformDiskConcentric(u);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

Vec3 squareToUniformTriangle(const Vec2& u) {
  const float s = std::sqrt(u.x);
  const float b0 = 1.0f - s;
  const float b1 = u.y * s;
  return {b0, b1, std::max(0.0f, 1.0f - b0 - b1)};
}

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

}  // namespace fs
