#pragma once
/// @file microfacet_model.h
/// Which microfacet distribution a rough reflection uses, and its functions dispatched by that choice: GGX
/// (common/materials/microfacet.h; glTF's, and every material's unless its scene file asks for another) or Beckmann
/// (common/materials/beckmann.h; Mitsuba's default for rough conductors). The GGX branch calls the GGX functions unchanged.
#include <cstdint>

#include "common/materials/beckmann.h"
#include "common/materials/microfacet.h"

namespace firstshot {

enum class MicrofacetModel : uint8_t { Ggx, Beckmann };

/// The specular microfacet BRDF without Fresnel, D·G2/(4 cos θ_i cos θ_o), in 1/sr.
inline float microfacetSpecular(MicrofacetModel m, const Vec3& wi, const Vec3& wo, float alpha) {
  return m == MicrofacetModel::Beckmann ? beckmannSpecular(wi, wo, alpha) : ggxSpecular(wi, wo, alpha);
}

/// A microfacet normal for reflecting @p wo (wo.z > 0): GGX's visible normals, Beckmann's D(h)·cos θ_h.
inline Vec3 sampleMicrofacetNormal(MicrofacetModel m, const Vec3& wo, float alpha, const Vec2& u) {
  return m == MicrofacetModel::Beckmann ? sampleBeckmannNormal(alpha, u) : sampleGgxVisibleNormal(wo, alpha, u);
}

/// Solid-angle density of wi = reflect(wo, h) for h drawn by sampleMicrofacetNormal.
inline float microfacetReflectionPdf(MicrofacetModel m, const Vec3& wi, const Vec3& wo, float alpha) {
  return m == MicrofacetModel::Beckmann ? beckmannReflectionPdf(wi, wo, alpha) : ggxReflectionPdf(wi, wo, alpha);
}

}  // namespace firstshot
