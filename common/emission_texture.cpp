// Emission that varies over a surface: the radiance at a point of a textured emitter (common/emission_texture.h).
#include "common/emission_texture.h"

#include "common/texture.h"

namespace fs {
namespace {

/// Barycentric coordinates (β, γ) of @p p projected onto the plane of triangle (a, b, c):
/// p ≈ a + β(b − a) + γ(c − a); (−1, −1) for a degenerate triangle.
Vec2d emitterBarycentric(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& p) {
  const Vec3d e1 = b - a, e2 = c - a, d = p - a;
  const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const double p1 = glm::dot(d, e1), p2 = glm::dot(d, e2), det = d11 * d22 - d12 * d12;
  if (!(det > 0.0)) return Vec2d(-1.0);
  return Vec2d(d22 * p1 - d12 * p2, d11 * p2 - d12 * p1) / det;
}

}  // namespace

bool emitsPerPoint(const MaterialDesc& m, const ShapeDesc& s) { return m.emissionTexture && s.hasUv(); }

Color emissionAt(const MaterialDesc& m, const Vec2& uv) { return m.emissionFactor * m.emissionTexture->lookup(uv); }

Vec2 faceUvAt(const ShapeDesc& s, size_t f, const Vec3d& p) {
  const Face& face = s.faces[f];
  int k1 = 1, k2 = 2;
  Vec2d bary = emitterBarycentric(s.vertices[face.v[0]], s.vertices[face.v[1]], s.vertices[face.v[2]], p);
  if (face.count == 4 && bary.x < 0.0) {
    k1 = 2, k2 = 3;
    bary = emitterBarycentric(s.vertices[face.v[0]], s.vertices[face.v[2]], s.vertices[face.v[3]], p);
  }
  const Vec2 a = s.cornerUv(f, 0), b = s.cornerUv(f, k1), c = s.cornerUv(f, k2);
  return a + float(bary.x) * (b - a) + float(bary.y) * (c - a);
}

Color meanEmissionOverTriangle(const MaterialDesc& m, const Vec2& uv0, const Vec2& uv1, const Vec2& uv2, int n) {
  Color sum(0.0f);
  forEachSubTriangleCentroid(n, [&](float b, float c) {
    sum += emissionAt(m, uv0 + b * (uv1 - uv0) + c * (uv2 - uv0));
  });
  return sum / float(n * n);
}

}  // namespace fs
