#pragma once
/// @file conductor_fresnel.h
/// The exact unpolarised Fresnel reflectance of a smooth conductor (a metal), per RGB channel, from its complex
/// index of refraction η + ik relative to the medium outside (Mitsuba's `conductor` and `roughconductor`).
///
/// Optics: with n² = (η² − k²) + 2iηk and w = √(n² − sin²θ) the root with Re w ≥ 0 and Im w ≥ 0 (the refracted wave
/// decays into the metal), the amplitude ratios of the two polarisations are
///   r_s = (cos θ − w)/(cos θ + w),     r_p = (n² cos θ − w)/(n² cos θ + w),
/// and F = (|r_s|² + |r_p|²)/2. k = 0 is a dielectric of index η (fresnelDielectric, total internal reflection
/// included when η < 1); η = 0, k = 1 reflects everything at every angle (n² = −1: |r_s| = |r_p| = 1), Mitsuba's
/// ideal mirror (`material="none"`) and the default here. F is the same for light arriving from either side of the
/// direction pair (it depends on the angle at the interface only), so reflection with it is reciprocal.
#include "common/util/math.h"

namespace firstshot {

/// The unpolarised Fresnel reflectance of a smooth interface into a medium of complex relative index η + ik.
/// @param cosThetaI |cos| of the angle of incidence, clamped to [0, 1]
/// @param eta real part η ≥ 0 of the index (over the outside medium's)
/// @param k extinction coefficient k ≥ 0
/// @return F in [0, 1]; 1 at grazing incidence (cosThetaI = 0)
float fresnelConductor(float cosThetaI, float eta, float k);

/// A conductor's Fresnel reflectance as a small value type: η and k per channel, and the cosine-weighted
/// hemispherical mean of F (computed once, for albedo()).
class ConductorFresnel {
 public:
  /// η = 0, k = 1: F = 1 at every angle, an ideal mirror.
  ConductorFresnel() = default;
  /// The conductor of relative index @p eta + i @p k per channel (each ≥ 0 and finite; validateScene checks
  /// the scene's).
  ConductorFresnel(const Color& eta, const Color& k);

  const Color& eta() const { return eta_; }
  const Color& k() const { return k_; }
  /// F per channel at |cos θ| = @p cosThetaI.
  Color eval(float cosThetaI) const {
    return {fresnelConductor(cosThetaI, eta_.x, k_.x), fresnelConductor(cosThetaI, eta_.y, k_.y),
            fresnelConductor(cosThetaI, eta_.z, k_.z)};
  }
  /// F at normal incidence, ((η − 1)² + k²)/((η + 1)² + k²).
  Color normalIncidence() const;
  /// ∫ F(cos θ) 2 cos θ d(cos θ) over [0, 1]: the directional albedo of the smooth conductor averaged over a
  /// uniformly lit hemisphere (1 for the ideal mirror; 0.0918 for k = 0, η = 1.5).
  const Color& hemisphericalMean() const { return mean_; }

  bool operator==(const ConductorFresnel& o) const { return eta_ == o.eta_ && k_ == o.k_; }

 private:
  Color eta_{0.0f}, k_{1.0f};
  Color mean_{1.0f};
};

}  // namespace firstshot
