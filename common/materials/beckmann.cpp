// The Beckmann microfacet distribution, its Smith masking and sampling (beckmann.h).
#include "common/materials/beckmann.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

float beckmannD(const Vec3& h, float alpha) {
  if (!(h.z > 0.0f)) return 0.0f;
  const float cos2 = h.z * h.z, sin2 = h.x * h.x + h.y * h.y;
  const float a2 = alpha * alpha;
  return std::exp(-sin2 / (cos2 * a2)) / (kPiF * a2 * cos2 * cos2);
}

float beckmannLambda(const Vec3& w, float alpha) {
  const float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return INFINITY;
  const float sin2 = w.x * w.x + w.y * w.y;
  if (!(sin2 > 0.0f)) return 0.0f;
  const float a = std::sqrt(z2 / sin2) / alpha;  // 1/(α tan θ)
  if (a > 9.0f) return 0.0f;  // e^(−81): below float resolution against the 1 of 1 + Λ
  constexpr float kInvSqrtPi = 0.5641895835f;
  return 0.5f * (std::exp(-a * a) * kInvSqrtPi / a - std::erfc(a));
}

Vec3 sampleBeckmannNormal(float alpha, const Vec2& u) {
  const float tan2 = -alpha * alpha * std::log1p(-std::min(u.x, 0x1.fffffep-1f));
  const float cosT = 1.0f / std::sqrt(1.0f + tan2);
  const float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
  const float phi = 2.0f * kPiF * u.y;
  return {sinT * std::cos(phi), sinT * std::sin(phi), cosT};
}

float beckmannReflectionPdf(const Vec3& wi, const Vec3& wo, float alpha) {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  const Vec3 h = glm::normalize(wi + wo);
  const float oh = glm::dot(wo, h);
  if (!(oh > 0.0f)) return 0.0f;
  return beckmannD(h, alpha) * h.z / (4.0f * oh);
}

float beckmannSpecular(const Vec3& wi, const Vec3& wo, float alpha) {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  const Vec3 h = glm::normalize(wi + wo);
  return beckmannD(h, alpha) * beckmannG2(wi, wo, alpha) / (4.0f * wi.z * wo.z);
}

}  // namespace firstshot
