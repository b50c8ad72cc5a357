#pragma once
/// @file rough_dielectric.h
/// Rough glass (frosted glass): microfacet reflection and refraction at a GGX interface (Walter, Marschner,
/// Li & Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces"), and its thin-pane cousin.
/// The distribution, the Smith masking and the sampling of visible normals are common/materials/microfacet.h's (the pbr
/// material's); α = ggxAlpha(roughness). Both models are non-delta: eval and pdf are densities, so light
/// sampling and MIS apply at such a surface. Roughness 0 is not these models: makeBSDF then builds the smooth
/// DielectricBSDF or ThinGlassBSDF (delta lobes), so a scene without roughness renders as before.
///
/// Conventions as common/materials/bsdf.h: wo.z > 0 is the outside. Both are written in the frame mirrored so that wo.z > 0,
/// with η the relative index η(other side)/η(wo side) (ior entering, 1/ior leaving).
#include "common/materials/thin_glass.h"
#include "common/util/math.h"

namespace firstshot {

struct BSDFQuery;

/// A rough dielectric interface (a solid of index ior, the normal outwards). With h the half vector,
///   reflection (wi on wo's side): f = F(wo·h) · D(h) G2 / (4 |cos θ_i| cos θ_o),          h ∝ wi + wo
///   refraction (opposite sides):  f = τ (1 − F(wo·h)) D(h) G2 |wi·h| |wo·h| / (|cos θ_i| cos θ_o (η wi·h + wo·h)²),
///                                 h ∝ −(η wi + wo), facing wo (wo·h > 0 > wi·h),
/// F the exact Fresnel reflectance of the microfacet (common/materials/fresnel.h), G2 the height-correlated Smith term
/// 1/(1 + Λ(wi) + Λ(wo)) for both lobes (Heitz 2014 gives a beta function for transmission; the simpler form is
/// the usual one and is symmetric), τ the transmittance tint. That refraction value is the radiance BSDF
/// (Radiance mode): light from wi to the viewer at wo, which holds the change of radiance 1/η² across the interface.
/// In Importance mode (a particle arriving from wo, leaving along wi) eval and sample give the adjoint
/// f*(wi, wo) = f(wo → wi), the same expression times η² (Veach 1997, §5.2): flux is not rescaled.
/// Energy: at small roughness R + T·η² → the smooth interface's R + (1 − R); it loses the energy of multiple
/// scattering between microfacets (no compensation), measured in tests/test_rough_glass.cpp.
/// Sampling: the reflection lobe with probability pR = F(|cos θ_o|) clamped to [0.02, 0.98] (the macro surface's
/// Fresnel), else the refraction lobe; each draws h from the visible normals of wo and reflects or refracts about
/// it. pdf() is the exact density of that mixture.
struct RoughDielectricBSDF {
  float ior = 1.5f;           ///< η_inside/η_outside, > 0
  Color transmittance{1.0f};  ///< tint τ applied on each refraction
  float roughness = 0.5f;     ///< perceptual roughness r ∈ (0, 1] (α = r²)

  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery& q) const;
  float pdf(const BSDFQuery& q) const;
  Color albedo() const { return transmittance; }
  /// The probability of sampling the reflection lobe for |cos θ_o| = @p cosO and relative index @p eta.
  static float reflectProbability(float cosO, float eta);
};

/// A rough thin pane (frosted window): the smooth pane's optics (common/materials/thin_glass.h, R(θ) and T(θ) summed over the
/// inter-reflections) per microfacet, with the transmitted light leaving where a reflection would, mirrored through
/// the pane. With w' = (wi.x, wi.y, |wi.z|·sign(wo.z)) (wi brought to wo's side), h ∝ w' + wo and c = wo·h:
///   f(wi, wo) = {R(c) on wo's side, T(c) on the other} · D(h) G2(w', wo) / (4 |cos θ_i| |cos θ_o|).
/// A ray is not displaced (as the smooth pane's), the transmitted lobe spreads around the straight-through direction
/// −wo exactly as the reflected one around the mirror direction, and the model has no refraction: f is reciprocal
/// and the same in both transport modes. A lossless pane (R + T = 1) transmits and reflects what the smooth one does
/// up to the microfacet multiple-scattering loss (the GGX white furnace's). Sampling: h from the visible normals,
/// reflected; then mirrored through the pane with probability pT = the smooth pane's T/(R + T) at |cos θ_o|
/// (clamped to [0.02, 0.98] when both are non-zero).
struct RoughThinGlassBSDF {
  ThinGlassBSDF pane;       ///< the pane's optics (transmittance at normal incidence, index)
  float roughness = 0.5f;   ///< perceptual roughness r ∈ (0, 1] (α = r²)

  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery& q) const;
  float pdf(const BSDFQuery& q) const;
  Color albedo() const { return pane.albedo(); }
  /// The probability of mirroring a sample through the pane for |cos θ_o| = @p cosO.
  float transmitProbability(float cosO) const;
};

}  // namespace firstshot
