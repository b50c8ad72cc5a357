#pragma once
/// @file beckmann.h
/// The Beckmann microfacet distribution, isotropic, in the local shading frame (z = macro normal): the normal
/// distribution, Smith's masking for it, the height-correlated masking-shadowing and the specular microfacet BRDF,
/// as common/materials/microfacet.h has them for GGX (the same α floor), and sampling of the normals by D(h)·cos θ_h.
///
/// D(h) = exp(−tan²θ_h/α²)/(π α² cos⁴θ_h); Smith's Λ(w) = (e^(−a²)/(a√π) − erfc(a))/2 with a = 1/(α tan θ_w).
/// Mitsuba's default for its rough conductors and plastics. Sampling draws h from D(h)·cos θ_h (tan²θ_h =
/// −α² ln(1 − u)) rather than from the visible normals as for GGX: unbiased, with a higher variance only at grazing
/// view angles (a reflection about a normal facing away from wo fails).
#include "common/util/math.h"

namespace firstshot {

/// The Beckmann normal distribution D(h) in 1/sr (∫ D(h) cos θ_h dω_h = 1); 0 for h.z ≤ 0. h is a unit vector.
float beckmannD(const Vec3& h, float alpha);

/// Smith's Λ(w) for Beckmann: G1(w) = 1/(1 + Λ(w)). w.z > 0 (∞ at w.z = 0).
float beckmannLambda(const Vec3& w, float alpha);

/// Height-correlated masking-shadowing G2(wi, wo) = 1/(1 + Λ(wi) + Λ(wo)) (both above the surface).
inline float beckmannG2(const Vec3& wi, const Vec3& wo, float alpha) {
  return 1.0f / (1.0f + beckmannLambda(wi, alpha) + beckmannLambda(wo, alpha));
}

/// A microfacet normal drawn from D(h)·cos θ_h from u ∈ [0,1)².
Vec3 sampleBeckmannNormal(float alpha, const Vec2& u);

/// Solid-angle density of wi = reflect(wo, h) when h is drawn by sampleBeckmannNormal: D(h)·h.z/(4 wo·h), with
/// h = normalize(wi + wo). 0 unless both are above.
float beckmannReflectionPdf(const Vec3& wi, const Vec3& wo, float alpha);

/// The specular microfacet BRDF without Fresnel, D·G2/(4 cos θ_i cos θ_o), in 1/sr (wi.z, wo.z > 0).
float beckmannSpecular(const Vec3& wi, const Vec3& wo, float alpha);

}  // namespace firstshot
