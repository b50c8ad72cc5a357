#pragma once
/// @file light_bounds.h
/// Spatial and directional bounds of an emitter or a cluster of emitters, and the importance
/// bound a light tree descends by (after Conty Estevez & Kulla 2018 and pbrt-v4's BVH light
/// sampler; our own formulation).
///
/// The emission of a cluster leaves points inside @c lo..hi, in directions within θo + θe of
/// the axis @c w: fully inside θo (the spread of the emitters' normals or spot axes), falling
/// off beyond it, nothing past θo + θe (π/2 for surfaces, the spot's falloff band for spots).
#include <algorithm>
#include <cmath>

#include "common/util/math.h"

namespace firstshot {

namespace detail {
inline float safeSqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
}  // namespace detail

struct LightBounds {
  Vec3 lo{0.0f}, hi{0.0f};  ///< axis-aligned box of the emitting points, m
  Vec3 w{0.0f, 0.0f, 1.0f}; ///< unit cone axis
  float phi = 0.0f;         ///< emitted power (mean over RGB), W
  float cosO = -1.0f;       ///< cos θo: spread of the normals / axes (−1: every direction)
  float cosE = 0.0f;        ///< cos θe: emission band beyond θo (0: a hemisphere past the cone)
  bool twoSided = false;    ///< emits along −w as well

  Vec3 centre() const { return 0.5f * (lo + hi); }

  /// An upper bound of the power-weighted, cosine-weighted inverse-square contribution that the
  /// cluster can make at @p p, whose receiving hemisphere is around the unit normal @p n (pass a
  /// zero vector for a receiver that takes light from every direction). Zero only where no
  /// emitter of the cluster can light @p p.
  float importance(const Vec3& p, const Vec3& n) const;
};

/// The importance bound of LightBounds::importance from precomputed quantities: the bounding
/// sphere (centre @p c, squared radius @p r2) of the box, the cone (@p w, cos/sin θo, cos θe),
/// the power @p phi. Shared by LightBounds and the light tree's compact nodes.
inline float boundImportance(const Vec3& c, float r2, const Vec3& w, float phi, float cosO, float sinO, float cosE,
                      bool twoSided, const Vec3& p, const Vec3& n) {
  if (!(phi > 0.0f)) return 0.0f;
  const Vec3 d = p - c;
  const float dist2 = glm::dot(d, d);
  const float d2 = std::max({dist2, r2, 1e-12f});
  const Vec3 wi = dist2 > 0.0f ? d * (1.0f / std::sqrt(dist2)) : w;  // from the cluster to p

  // Angle θb that the bounding sphere subtends at p (π when p is inside it).
  float cosB = -1.0f, sinB = 0.0f;
  if (dist2 > r2) {
    const float sin2B = r2 / dist2;
    cosB = detail::safeSqrt(1.0f - sin2B);
    sinB = std::sqrt(sin2B);
  }

  // cos(max(0, θw − θo − θb)), θw the angle between the axis and the direction to p.
  float cosW = glm::dot(w, wi);
  if (twoSided) cosW = std::abs(cosW);
  float cosP = 1.0f;
  if (cosW < cosO) {
    const float sinW = detail::safeSqrt(1.0f - cosW * cosW);
    const float cosWO = cosW * cosO + sinW * sinO;  // cos, sin of θw − θo
    const float sinWO = sinW * cosO - cosW * sinO;
    if (cosWO < cosB) cosP = cosWO * cosB + sinWO * sinB;
  }
  if (cosP <= cosE) return 0.0f;
  float value = phi * cosP / d2;

  // Receiver: cos(max(0, θi − θb)) for the angle θi between n and the direction to the cluster.
  if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) {
    const float cosI = -glm::dot(wi, n);
    if (cosI < cosB) {
      const float sinI = detail::safeSqrt(1.0f - cosI * cosI);
      const float cosPI = cosI * cosB + sinI * sinB;
      if (cosPI <= 0.0f) return 0.0f;
      value *= cosPI;
    }
  }
  return value;
}

/// Bounds of two clusters together: box union, cone union, summed power.
LightBounds unite(const LightBounds& a, const LightBounds& b);

/// The directional measure M_Ω of the bounds' emission (pbrt-v4's surface-area-orientation
/// heuristic): 2π(1 − cos θo) + π/2·(cos θo − cos(2θw − θo)) + π(θw − θo) sin θo, θw = min(θo + θe, π).
float orientationMeasure(const LightBounds& b);

}  // namespace firstshot
