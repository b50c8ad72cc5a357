// Importance bound and union of light bounds.
#include "render/lights/light_bounds.h"

#include <algorithm>

namespace firstshot {

namespace {

using detail::safeSqrt;

/// Cone (axis, half-angle θ) that contains both cones.
void uniteCones(Vec3 wa, float ta, Vec3 wb, float tb, Vec3& w, float& theta) {
  if (tb > ta) std::swap(wa, wb), std::swap(ta, tb);
  if (ta >= kPiF) {
    w = wa, theta = kPiF;
    return;
  }
  const float td = std::acos(std::clamp(glm::dot(wa, wb), -1.0f, 1.0f));
  if (std::min(td + tb, kPiF) <= ta) {
    w = wa, theta = ta;
    return;
  }
  const float to = 0.5f * (ta + td + tb);
  if (to >= kPiF) {
    w = wa, theta = kPiF;
    return;
  }
  // Rotate wa towards wb by to − ta.
  const Vec3 axis = glm::cross(wa, wb);
  const float len = glm::length(axis);
  if (!(len > 1e-7f)) {  // (anti)parallel axes that do not nest: no narrower cone is safe
    w = wa, theta = kPiF;
    return;
  }
  const Vec3 k = axis / len;
  const float r = to - ta, c = std::cos(r), s = std::sin(r);
  w = glm::normalize(wa * c + glm::cross(k, wa) * s + k * glm::dot(k, wa) * (1.0f - c));
  theta = to;
}

}  // namespace

float LightBounds::importance(const Vec3& p, const Vec3& n) const {
  const Vec3 diag = hi - lo;
  return boundImportance(centre(), 0.25f * glm::dot(diag, diag), w, phi, cosO, safeSqrt(1.0f - cosO * cosO), cosE,
                         twoSided, p, n);
}

LightBounds unite(const LightBounds& a, const LightBounds& b) {
  if (!(a.phi > 0.0f)) return b;
  if (!(b.phi > 0.0f)) return a;
  LightBounds u;
  u.lo = glm::min(a.lo, b.lo);
  u.hi = glm::max(a.hi, b.hi);
  float theta;
  uniteCones(a.w, std::acos(std::clamp(a.cosO, -1.0f, 1.0f)), b.w, std::acos(std::clamp(b.cosO, -1.0f, 1.0f)), u.w, theta);
  u.cosO = std::cos(theta);
  if (theta >= kPiF) u.cosO = -1.0f;
  u.cosE = std::min(a.cosE, b.cosE);
  u.phi = a.phi + b.phi;
  u.twoSided = a.twoSided || b.twoSided;
  return u;
}

float orientationMeasure(const LightBounds& b) {
  const float to = std::acos(std::clamp(b.cosO, -1.0f, 1.0f));
  const float te = std::acos(std::clamp(b.cosE, -1.0f, 1.0f));
  const float tw = std::min(to + te, kPiF);
  const float sinO = std::sin(to);
  return 2.0f * kPiF * (1.0f - b.cosO) + 0.5f * kPiF * (b.cosO - std::cos(2.0f * tw - to)) + kPiF * (tw - to) * sinO;
}

}  // namespace firstshot
