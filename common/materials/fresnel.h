#pragma once
/// @file fresnel.h
/// Smooth-interface optics in the local shading frame (z = normal): mirror reflection, Snell
/// refraction and the exact unpolarised Fresnel reflectance of a dielectric.
#include <algorithm>

#include "common/util/math.h"

namespace firstshot {

/// Mirror reflection of @p w about the local normal (both vectors point away from the surface).
inline Vec3 reflectLocal(const Vec3& w) { return {-w.x, -w.y, w.z}; }

/// Unpolarised Fresnel reflectance of a smooth dielectric interface.
/// @param cosThetaI cosine between the incident direction and the normal, in [0, 1] (the side the
///        light comes from does not matter: pass |cos|)
/// @param eta relative index η_t/η_i (transmitted side over incident side)
/// @param cosThetaT out: cosine of the refraction angle (≥ 0), 0 on total internal reflection
/// @return R in [0, 1]; exactly 1 on total internal reflection. T = 1 − R.
inline float fresnelDielectric(float cosThetaI, float eta, float* cosThetaT = nullptr) {
  cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
  const float sin2T = (1.0f - cosThetaI * cosThetaI) / (eta * eta);
  if (sin2T >= 1.0f) {
    if (cosThetaT) *cosThetaT = 0.0f;
    return 1.0f;
  }
  const float cosT = std::sqrt(1.0f - sin2T);
  if (cosThetaT) *cosThetaT = cosT;
  const float rs = (cosThetaI - eta * cosT) / (cosThetaI + eta * cosT);
  const float rp = (eta * cosThetaI - cosT) / (eta * cosThetaI + cosT);
  return 0.5f * (rs * rs + rp * rp);
}

/// Refracted direction for @p w (pointing away from the surface, w.z ≠ 0) through an interface of
/// relative index @p eta = η(other side)/η(side of w), given cosThetaT from fresnelDielectric.
/// The result points away from the surface on the opposite side (sign of z flipped).
inline Vec3 refractLocal(const Vec3& w, float eta, float cosThetaT) {
  const float s = 1.0f / eta;
  return {-w.x * s, -w.y * s, w.z > 0.0f ? -cosThetaT : cosThetaT};
}

}  // namespace firstshot
