#pragma once
/// @file form_factors.h
/// Closed-form radiometry (docs/firstshot-format.md, "Estimators"), for the small-light rule, the first-shot
/// factors (preprocess/coverage.h) and their per-point evaluation (render/firstshot/lighting.h), and tests.
#include <cmath>
#include <vector>

#include "common/util/math.h"

namespace firstshot::analytic {

/// Solid angle of triangle (a, b, c) seen from @p eye (Van Oosterom–Strackee), in [0, 2π].
inline double solidAngleTriangle(const Vec3d& eye, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d r1 = a - eye, r2 = b - eye, r3 = c - eye;
  const double l1 = glm::length(r1), l2 = glm::length(r2), l3 = glm::length(r3);
  const double num = std::abs(glm::dot(r1, glm::cross(r2, r3)));
  const double den = l1 * l2 * l3 + glm::dot(r1, r2) * l3 + glm::dot(r1, r3) * l2 + glm::dot(r2, r3) * l1;
  return 2.0 * std::atan2(num, den);
}

/// Solid angle of a convex planar polygon (fan of triangles) seen from @p eye.
inline double solidAnglePolygon(const Vec3d& eye, const std::vector<Vec3d>& poly) {
  double sum = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) sum += solidAngleTriangle(eye, poly[0], poly[i], poly[i + 1]);
  return sum;
}

/// Point-to-polygon form factor for a Lambertian receiver at @p x with unit normal @p n:
/// F = (1/2π) Σ γ_i n·(R_i×R_{i+1})/|R_i×R_{i+1}|. The sign convention makes F ≥ 0 for a polygon in
/// front of the receiver whatever the polygon's winding. Irradiance from a uniform polygon: E = π·L·F.
/// Each vertex direction is normalised once (the hot loop of reading a .fsd table's grouped factors).
inline double pointPolygonFormFactor(const Vec3d& x, const Vec3d& n, const Vec3d* poly, size_t count) {
  Vec3d dirs[16];
  std::vector<Vec3d> many;  // polygons above 16 vertices (none in the patch meshes)
  Vec3d* dir = count <= 16 ? dirs : (many.resize(count), many.data());
  for (size_t i = 0; i < count; ++i) dir[i] = glm::normalize(poly[i] - x);
  double sum = 0;
  for (size_t i = 0; i < count; ++i) {
    const Vec3d a = dir[i], b = dir[(i + 1) % count];
    const Vec3d c = glm::cross(a, b);
    const double len = glm::length(c);
    if (len <= 0) continue;
    const double gamma = std::atan2(len, glm::dot(a, b));
    sum += gamma * glm::dot(n, c / len);
  }
  return std::abs(sum) / (2.0 * kPi);
}

/// The same for a polygon held in a vector.
inline double pointPolygonFormFactor(const Vec3d& x, const Vec3d& n, const std::vector<Vec3d>& poly) {
  return pointPolygonFormFactor(x, n, poly.data(), poly.size());
}

/// Sutherland–Hodgman: writes to @p out (room for n+1 vertices) the part of the convex polygon
/// @p in (n vertices) where dot(p − origin, normal) ≥ offset; returns its vertex count.
inline int clipPolygonToPlane(const Vec3d* in, int n, const Vec3d& origin, const Vec3d& normal, double offset, Vec3d* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3d& a = in[i];
    const Vec3d& b = in[(i + 1) % n];
    const double da = glm::dot(a - origin, normal) - offset, db = glm::dot(b - origin, normal) - offset;
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m;
}

/// Solid angle (sr) of a convex planar polygon of @p count ≤ 8 vertices seen from @p eye.
inline double polygonSolidAngle(const Vec3d& eye, const Vec3d* poly, int count) {
  double s = 0;
  for (int i = 1; i + 1 < count; ++i) s += solidAngleTriangle(eye, poly[0], poly[i], poly[i + 1]);
  return s;
}

/// ∫ cosθ dω (sr) over the part of a convex planar polygon (≤ 8 vertices) above the plane through
/// @p eye with unit normal @p n: π × the point-to-polygon form factor, the polygon clipped first.
inline double polygonCosineSolidAngle(const Vec3d& eye, const Vec3d& n, const Vec3d* poly, int count) {
  Vec3d clipped[9];
  const int m = clipPolygonToPlane(poly, count, eye, n, 0.0, clipped);
  if (m < 3) return 0.0;
  return kPi * pointPolygonFormFactor(eye, n, clipped, size_t(m));
}

/// Area (m²) of a planar polygon projected along @p direction (any length).
inline double polygonProjectedArea(const Vec3d& direction, const Vec3d* poly, int count) {
  Vec3d cross(0.0);
  for (int i = 1; i + 1 < count; ++i) cross += glm::cross(poly[i] - poly[0], poly[i + 1] - poly[0]);
  return 0.5 * std::abs(glm::dot(cross, glm::normalize(direction)));
}

/// Form factor between parallel, directly opposed rectangles a×b at distance c.
inline double parallelRectanglesFormFactor(double a, double b, double c) {
  const double X = a / c, Y = b / c;
  const double X2 = X * X, Y2 = Y * Y;
  return 2.0 / (kPi * X * Y) *
         (std::log(std::sqrt((1 + X2) * (1 + Y2) / (1 + X2 + Y2))) + X * std::sqrt(1 + Y2) * std::atan(X / std::sqrt(1 + Y2)) +
          Y * std::sqrt(1 + X2) * std::atan(Y / std::sqrt(1 + X2)) - X * std::atan(X) - Y * std::atan(Y));
}

/// Irradiance from an isotropic point light of power @p phi at height @p h, horizontal offset @p x.
inline double pointLightIrradiance(double phi, double h, double x) {
  return phi * h / (4.0 * kPi * std::pow(h * h + x * x, 1.5));
}

}  // namespace firstshot::analytic
