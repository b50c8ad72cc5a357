#pragma once
/// @file sampling.h
/// Warps from the unit square [0,1)² to directions and points, each with its density (Nori style:
/// squareToX(u) and squareToXPdf(...)). Directions are unit vectors in a local frame whose z axis is
/// the normal (or the lobe axis); densities are per unit solid angle unless stated otherwise.
/// Every warp maps the open square to valid output; inputs on the closed square [0,1]² are safe.
#include <algorithm>
#include <cmath>

#include "common/util/math.h"

namespace firstshot {

namespace detail {
/// cos t and sin t for |t| ≤ π/4 by their Taylor polynomials (degree 8 and 7): absolute error
/// below 4·10⁻⁷ there (float rounding included), without the range reduction and branches of the library's sincosf.
inline void sinCosQuarter(float t, float& c, float& s) {
  const float t2 = t * t;
  c = 1.0f + t2 * (-1.0f / 2 + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320))));
  s = t * (1.0f + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040))));
}
}  // namespace detail

/// Uniform point on the unit disk by Shirley & Chiu's concentric mapping (low distortion,
/// preserves stratification). Density 1/π per unit area. Inline and without branches on the
/// sector: it runs at every path vertex.
inline Vec2 squareToUniformDiskConcentric(const Vec2& u) {
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  // Sector |a| > |b|: r = a, φ = π/4·b/a; else r = b, φ = π/2 − π/4·a/b (cos and sin swap).
  const bool wide = std::abs(a) > std::abs(b);
  const float r = wide ? a : b;
  const float ratio = r != 0.0f ? (wide ? b : a) / r : 0.0f;
  float c, s;
  detail::sinCosQuarter(0.25f * kPiF * ratio, c, s);
  return wide ? Vec2(r * c, r * s) : Vec2(r * s, r * c);
}
inline float squareToUniformDiskConcentricPdf(const Vec2& p) {
  return p.x * p.x + p.y * p.y <= 1.0f ? kInvPiF : 0.0f;
}

/// Uniform direction on the unit sphere (z = 1 − 2u.x, φ = 2π u.y). Density 1/(4π).
Vec3 squareToUniformSphere(const Vec2& u);
inline float squareToUniformSpherePdf() { return 0.25f * kInvPiF; }

/// Uniform direction on the upper hemisphere z ≥ 0 (z = u.x, φ = 2π u.y). Density 1/(2π) for z ≥ 0, else 0.
Vec3 squareToUniformHemisphere(const Vec2& u);
inline float squareToUniformHemispherePdf(const Vec3& w) { return w.z >= 0.0f ? 0.5f * kInvPiF : 0.0f; }

/// Cosine-weighted direction on the upper hemisphere (Malley's method: concentric disk lifted to the
/// hemisphere). Density cosθ/π for z > 0, else 0.
inline Vec3 squareToCosineHemisphere(const Vec2& u) {
  // The disk point's radius is the concentric mapping's r = max(|a|, |b|): z = √(1 − r²) does not
  // wait for the angle's division and polynomial, so the two run side by side (a hot path).
  const float r = std::max(std::abs(2.0f * u.x - 1.0f), std::abs(2.0f * u.y - 1.0f));
  const float z = std::sqrt(std::max(0.0f, 1.0f - r * r));
  const Vec2 d = squareToUniformDiskConcentric(u);
  return {d.x, d.y, z};
}
inline float squareToCosineHemispherePdf(const Vec3& w) { return w.z > 0.0f ? w.z * kInvPiF : 0.0f; }

/// Uniform point on a triangle as barycentric coordinates (b0, b1, b2), b0 = 1 − √u.x,
/// b1 = u.y·√u.x, b2 = 1 − b0 − b1; the point is b0·p0 + b1·p1 + b2·p2. Density 1/area per unit
/// area of the triangle (2 per unit area of the (b1, b2) parameter triangle).
inline Vec3 squareToUniformTriangle(const Vec2& u) {
  const float s = std::sqrt(u.x);
  const float b0 = 1.0f - s;
  const float b1 = u.y * s;
  return {b0, b1, std::max(0.0f, 1.0f - b0 - b1)};
}
inline float squareToUniformTrianglePdf(float area) { return area > 0.0f ? 1.0f / area : 0.0f; }

/// Phong lobe around +z: density (n+1)/(2π)·cos^n α on the hemisphere cos α > 0 around the axis
/// (α = angle to the axis), 0 elsewhere; cos α = u.x^{1/(n+1)}, φ = 2π u.y. Requires n ≥ 0.
Vec3 squareToPhongLobe(const Vec2& u, float n);
/// Density of squareToPhongLobe given cos α (the cosine between the direction and the lobe axis).
inline float squareToPhongLobePdf(float cosAlpha, float n) {
  return cosAlpha > 0.0f ? (n + 1.0f) * 0.5f * kInvPiF * std::pow(cosAlpha, n) : 0.0f;
}
/// Phong lobe around an arbitrary unit @p axis (same density, measured against that axis).
inline Vec3 samplePhongLobe(const Vec3& axis, float n, const Vec2& u) {
  return Frame(axis).toWorld(squareToPhongLobe(u, n));
}

/// Stratified cosine-weighted hemisphere sampling for irradiance caching (Ward, Rubinstein & Clear
/// 1988, eq. 2): the hemisphere is cut into M polar × N azimuthal cells of equal projected solid
/// angle π/(MN), cell (j, k) spanning sin²θ ∈ [j/M, (j+1)/M) and φ ∈ [2πk/N, 2π(k+1)/N); @p u
/// jitters inside the cell. (The paper prints θ_j = asin(√(j·X_j/n)); the stratified form is
/// asin(√((j − X_j)/n)) for j = 1..n, i.e. the cell above with j shifted to start at 0.)
/// Over a uniformly chosen cell the density is cosθ/π (squareToCosineHemispherePdf), so
/// E = ∫ L cosθ dω ≈ π/(MN) · Σ_{j,k} L(ω_jk) with one sample per cell. Ward uses N = 2M.
Vec3 squareToCosineHemisphereStratum(int j, int k, int M, int N, const Vec2& u);

}  // namespace firstshot
