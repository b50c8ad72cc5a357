#pragma once
/// @file microfacet.h
/// The Trowbridge-Reitz (GGX) microfacet distribution, isotropic, in the local shading frame
/// (z = macro normal), with the height-correlated Smith masking-shadowing function and sampling of
/// the visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible Normals").
///
/// Roughness: α is the GGX width; glTF's perceptual roughness r maps to α = r² (ggxAlpha). α is
/// floored at kMinGgxAlpha = 1e-3, so that a "smooth" (r = 0) surface stays a very narrow but
/// finite lobe: eval, pdf and sample stay consistent and no integrator needs a mixed delta +
/// non-delta BSDF (docs/architecture.md, "Materials"). The price: first-shot's sum over light samples
/// cannot resolve so sharp a lobe, so polished surfaces lose the reflections of replaced lights
/// (docs/measurements.md). At the floor D(h) peaks at 1/(πα²) ≈ 3·10⁵ sr⁻¹, still exact in float
/// because D is evaluated from sin²θ_h and cos²θ_h separately.
///
/// Every function takes directions in the upper hemisphere (z > 0); callers of two-sided models
/// mirror both directions first.
#include <algorithm>

#include "common/util/math.h"

namespace firstshot {

/// Smallest GGX α used (a perceptual roughness below √1e-3 ≈ 0.032 is this α).
inline constexpr float kMinGgxAlpha = 1e-3f;

/// α = max(r², kMinGgxAlpha) for a perceptual (glTF) roughness r ∈ [0, 1].
inline float ggxAlpha(float roughness) { return std::max(roughness * roughness, kMinGgxAlpha); }

/// The GGX normal distribution D(h) in 1/sr (∫ D(h) cos θ_h dω_h = 1); 0 for h.z ≤ 0. h is a unit vector.
float ggxD(const Vec3& h, float alpha);

/// Smith's Λ(w) for GGX: G1(w) = 1/(1 + Λ(w)). w.z > 0.
float ggxLambda(const Vec3& w, float alpha);

/// Smith masking G1(w) = 1/(1 + Λ(w)), in [0, 1].
inline float ggxG1(const Vec3& w, float alpha) { return 1.0f / (1.0f + ggxLambda(w, alpha)); }

/// Height-correlated masking-shadowing G2(wi, wo) = 1/(1 + Λ(wi) + Λ(wo)) (both above the surface).
inline float ggxG2(const Vec3& wi, const Vec3& wo, float alpha) {
  return 1.0f / (1.0f + ggxLambda(wi, alpha) + ggxLambda(wo, alpha));
}

/// A microfacet normal h drawn from the distribution of normals visible from @p wo (wo.z > 0),
/// D_wo(h) = G1(wo)·max(0, wo·h)·D(h)/wo.z, from u ∈ [0,1)² (Heitz 2018).
Vec3 sampleGgxVisibleNormal(const Vec3& wo, float alpha, const Vec2& u);

/// Solid-angle density of wi = reflect(wo, h) when h is drawn by sampleGgxVisibleNormal:
/// D_wo(h)/(4 wo·h) = G1(wo)·D(h)/(4 wo.z), with h = normalize(wi + wo). 0 unless both are above.
float ggxReflectionPdf(const Vec3& wi, const Vec3& wo, float alpha);

/// The specular microfacet BRDF without Fresnel, D·G2/(4 cos θ_i cos θ_o), in 1/sr (wi.z, wo.z > 0).
float ggxSpecular(const Vec3& wi, const Vec3& wo, float alpha);

/// Schlick's Fresnel approximation F0 + (1 − F0)(1 − c)⁵ for the cosine c ∈ [0, 1].
inline Color schlickFresnel(const Color& f0, float c) {
  const float m = std::clamp(1.0f - c, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (Color(1.0f) - f0) * (m2 * m2 * m);
}

}  // namespace firstshot
