#pragma once
/// @file spot_cone.h
/// Emission profiles of the positional lights, shared by the preprocessor and the renderer so that
/// both stages see exactly the same light. Code that evaluates a light uses EmissionProfile
/// (common/lights/emission_profile.h), which also covers IES tables; this file holds the closed forms.
///
/// - Point light: isotropic, intensity I = Φ/(4π) in every direction.
/// - Spot light: I(θ) = I0 · spotProfile(cos θ), θ the angle to the axis. The profile is 1 inside
///   the inner half-angle, 0 outside the outer half-angle and a smoothstep in cos θ between them.
///   Since a smoothstep over [a, b] integrates to (b − a)/2, the total power is
///   Φ = 2π·I0·[(1 − cos inner) + (cos inner − cos outer)/2], which fixes I0 (spotIntensity0).
/// - Directional light: irradiance E⊥ on a plane facing it; LightDesc::direction is the direction
///   the light travels in.
#include <algorithm>
#include <cmath>

#include "common/lights/photometry.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// Intensity of an isotropic point light, Φ/(4π) in W/sr.
inline Color pointIntensity(const LightDesc& l) { return l.power * static_cast<float>(0.25 * kInvPi); }

/// A spot's cone, precomputed: the profile without trigonometry per call.
struct SpotCone {
  double cosInner = 1.0, cosOuter = 1.0;
  SpotCone() = default;
  explicit SpotCone(const LightDesc& l)
      : cosInner(std::cos(glm::radians(l.innerAngleDeg))), cosOuter(std::cos(glm::radians(l.outerAngleDeg))) {}

  /// Profile in [0, 1] for the cosine of the angle between the emitted direction and the axis:
  /// 1 for cosθ ≥ cos(inner), 0 for cosθ ≤ cos(outer), smoothstep in cosθ between.
  /// A hard-edged spot (inner == outer) is a step: 1 for cosθ ≥ cos(inner).
  double profile(double c) const {
    if (c >= cosInner) return 1.0;
    if (c <= cosOuter || !(cosInner > cosOuter)) return 0.0;
    const double t = (c - cosOuter) / (cosInner - cosOuter);
    return t * t * (3.0 - 2.0 * t);
  }
  /// Integral of profile() over the sphere of directions, in sr:
  /// 2π·[(1 − cos inner) + (cos inner − cos outer)/2].
  double integral() const { return 2.0 * kPi * ((1.0 - cosInner) + 0.5 * (cosInner - cosOuter)); }
};

/// The profile of spot light @p l (SpotCone::profile).
inline float spotProfile(const LightDesc& l, float cosTheta) {
  return static_cast<float>(SpotCone(l).profile(cosTheta));
}

/// Integral of spotProfile over the sphere of directions, in sr (SpotCone::integral).
inline double spotProfileIntegral(const LightDesc& l) { return SpotCone(l).integral(); }

/// Power Φ = I0·∫profile dω, W, of point or spot light @p l (not IES) with luminous intensity @p candela, cd, on its
/// axis (a point light: in every direction) and RGB weights @p rgb (photometry::toRadiometric): the JSON's "candela"
/// key and glTF's KHR_lights_punctual point and spot intensities.
inline Color powerFromCandela(const LightDesc& l, double candela, const Color& rgb) {
  const double solidAngle = l.type == LightType::Point ? 4.0 * kPi : spotProfileIntegral(l);
  return photometry::toRadiometric(candela * solidAngle, rgb);
}

/// On-axis intensity I0 = Φ / spotProfileIntegral of a spot light in W/sr, so that the total
/// emitted power is Φ. Zero for a spot of zero solid angle.
inline Color spotIntensity0(const LightDesc& l) {
  const double solidAngle = spotProfileIntegral(l);
  if (!(solidAngle > 0)) return Color(0.0f);
  return l.power * static_cast<float>(1.0 / solidAngle);
}

/// Intensity of a spot light in the world direction @p w (unit, pointing away from the light).
inline Color spotIntensity(const LightDesc& l, const Vec3& w) {
  const float cosTheta = glm::dot(w, Vec3(l.direction));
  return spotIntensity0(l) * spotProfile(l, cosTheta);
}

}  // namespace firstshot
