// The GGX microfacet distribution, Smith masking and visible-normal sampling (microfacet.h).
#include "common/materials/microfacet.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

float ggxD(const Vec3& h, float alpha) {
  if (!(h.z > 0.0f)) return 0.0f;
  // α²/(π(α²cos² + sin²)²) = 1/(πα²x²) with x = sin²/α² + cos²: no cancellation near the peak.
  const float a2 = alpha * alpha;
  const float x = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
  return 1.0f / (kPiF * a2 * x * x);
}

float ggxLambda(const Vec3& w, float alpha) {
  const float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return INFINITY;
  const float a2tan2 = alpha * alpha * (w.x * w.x + w.y * w.y) / z2;
  return 0.5f * (std::sqrt(1.0f + a2tan2) - 1.0f);
}

Vec3 sampleGgxVisibleNormal(const Vec3& wo, float alpha, const Vec2& u) {
  // Stretch to the hemisphere configuration (α = 1), sample the projected area of the visible
  // hemisphere there, and unstretch.
  const Vec3 v = glm::normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3 t1 = len2 > 0.0f ? Vec3(-v.y, v.x, 0.0f) / std::sqrt(len2) : Vec3(1.0f, 0.0f, 0.0f);
  const Vec3 t2 = glm::cross(v, t1);
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPiF * u.y;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.0f + v.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
  const Vec3 n = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * v;
  return glm::normalize(Vec3(alpha * n.x, alpha * n.y, std::max(0.0f, n.z)));
}

float ggxReflectionPdf(const Vec3& wi, const Vec3& wo, float alpha) {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  const Vec3 h = glm::normalize(wi + wo);
  return ggxG1(wo, alpha) * ggxD(h, alpha) / (4.0f * wo.z);
}

float ggxSpecular(const Vec3& wi, const Vec3& wo, float alpha) {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  const Vec3 h = glm::normalize(wi + wo);
  return ggxD(h, alpha) * ggxG2(wi, wo, alpha) / (4.0f * wi.z * wo.z);
}

}  // namespace firstshot
