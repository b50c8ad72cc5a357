#pragma once
/// @file light_bounds.h
/// Spatial and directional bounds of an emitter or a cluster of emitters, and the importance
/// bound a light tree descends by (after Conty Estevez & Kulla 2018 and pbrt-v4's BVH light
/// sampler; our own formulation).
///
/// The emission of a cluster leaves points inside @c lo..hi, in directions within θo + θe of
/// the axis @c w: fully inside θo (the spread of the emitters' normals or spot axes), falling
/// off beyond it, nothing past θo + θe (π/2 for surfaces, the spot's falloff band for spots).
#include <cmath>

#include "common/math.h"

namespace fs {

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

/// Bounds of two clusters together: box union, cone union, summed power.
LightBounds unite(const LightBounds& a, const LightBounds& b);

/// The directional measure M_Ω of the bounds' emission (pbrt-v4's surface-area-orientation
/// heuristic): 2π(1 − cos θo) + π/2·(cos θo − cos(2θw − θo)) + π(θw − θo) sin θo, θw = min(θo + θe, π).
float orientationMeasure(const LightBounds& b);

}  // namespace fs
