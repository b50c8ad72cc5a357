#pragma once
/// @file mitsuba_lobes.h
/// The numbers that map Mitsuba 0.6's reflectance models without a counterpart here onto the nearest material of the
/// project (common/formats/mitsuba/mitsuba_bsdf.cpp): the albedo of Mitsuba's Oren–Nayar `roughdiffuse`, the albedo at normal
/// incidence of its `ward` lobe, and the Phong exponent whose lobe about the mirror direction is as wide as a
/// Beckmann (Ward) lobe of roughness α. docs/scene-format.md, "Mitsuba 3 XML scenes", states how they are used.

namespace firstshot::mitsuba {

/// The white-sky albedo of Mitsuba's `roughdiffuse` (Oren and Nayar 1994 as Mitsuba 0.6 writes it, with σ = α/√2):
/// the fraction of light arriving from a uniformly bright hemisphere (cosine-weighted over incidence) that it reflects,
/// single·ρ + twice·ρ² for reflectance ρ (the ρ² term is light reflected between two facets of a groove; the fast
/// approximation has none). A midpoint rule in sin²θi, sin²θo and φo − φi (48 × 48 × 64 points).
struct OrenNayarAlbedo {
  double single = 1, twice = 0;
  double at(double rho) const { return single * rho + twice * rho * rho; }
};
OrenNayarAlbedo orenNayarAlbedo(double alpha, bool fastApproximation);

/// The albedo at normal incidence of Mitsuba's Ward lobe of isotropic roughness @p alpha and unit
/// specular_reflectance, for its variant "ward", "ward-duer" or "balanced" (a midpoint rule over the outgoing angle).
double wardAlbedoAtNormalIncidence(double alpha, const char* variant);

/// The exponent n of a Phong lobe about the mirror direction, cosⁿ θ, as wide at normal incidence as a Beckmann or
/// Ward lobe of roughness α: Walter et al. (2007) give the half-vector exponent 2/α² − 2 of the same width, and the
/// angle to the mirror direction is twice the half vector's, so n = (2/α² − 2)/4 (0 from α = 1 on).
double phongExponentOfRoughness(double alpha);

}  // namespace firstshot::mitsuba
