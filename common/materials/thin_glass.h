#pragma once
/// @file thin_glass.h
/// A thin glass pane (a window): a surface that reflects about its normal and transmits straight
/// through, without displacing the ray (Radiance's `glass`, Mitsuba's `thindielectric`). Two delta lobes.
///
/// Optics, per polarisation (s and p, then their mean): one interface reflects r(θ) (Fresnel, index
/// `ior` against 1); inside, one pass through the glass keeps a(θ) = a0^(1/cos θt) of the light (θt the
/// refraction angle: the path through a slab of thickness d is d/cos θt). Summing the inter-reflections
/// between the two faces (a geometric series),
///   R(θ) = r + r (1 − r)² a² / (1 − r² a²),     T(θ) = (1 − r)² a / (1 − r² a²).
/// a0 (per RGB channel) is solved from the pane's given transmittance τ at normal incidence, where
/// r = r0 = ((ior − 1)/(ior + 1))²: τ r0² a0² + (1 − r0)² a0 − τ = 0 (the positive root). A lossless
/// pane (a0 = 1) transmits (1 − r0)/(1 + r0), 0.9183 at ior 1.52: τ may not exceed it (maxTransmittance).
/// R + T ≤ 1 at every angle; T → 0 and R → 1 at grazing incidence.
#include "common/util/math.h"

namespace firstshot {

struct BSDFQuery;

/// The scene format's defaults (docs/scene-format.md): clear 6 mm soda-lime float glass, whose visible
/// transmittance at normal incidence is about 0.88, and its index.
inline constexpr float kThinGlassTransmittance = 0.88f;
inline constexpr float kThinGlassIor = 1.52f;

struct ThinGlassBSDF {
  float ior = 1.52f;   ///< refractive index of the glass (air outside), > 0
  Color a0{1.0f};      ///< internal transmittance of one pass at normal incidence, per channel, in [0, 1]

  ThinGlassBSDF() = default;
  /// The pane of index @p ior that transmits @p tau at normal incidence (each channel in
  /// [0, maxTransmittance(ior)]; larger values are taken as that bound).
  ThinGlassBSDF(const Color& tau, float ior);
  /// The largest normal-incidence transmittance of a pane of index @p ior: a lossless one's (1 − r0)/(1 + r0).
  static float maxTransmittance(float ior);

  /// The pane's transmittance T(θ) for light crossing it at |cos θ| = @p cosTheta (either side).
  Color transmittance(float cosTheta) const;
  /// The pane's reflectance R(θ) at |cos θ| = @p cosTheta.
  Color reflectance(float cosTheta) const;
  /// Both at once (one Fresnel evaluation).
  void reflectTransmit(float cosTheta, Color& R, Color& T) const;
  /// The probability with which sample() takes the transmission lobe: mean(T)/(mean(R) + mean(T)).
  static float transmitProbability(const Color& R, const Color& T);

  /// Transmission (wi = −wo, pdf = transmitProbability, weight T/pdf) or reflection about the normal
  /// (pdf = 1 − that, weight R/pdf), chosen by u.x; q.specular = true, q.eta = 1 (no refraction).
  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery&) const { return Color(0.0f); }
  float pdf(const BSDFQuery&) const { return 0.0f; }
  /// R + T at normal incidence (what the pane does not absorb).
  Color albedo() const;
};

}  // namespace firstshot
