// Patches to their source faces, and points to barycentric coordinates in them (common/patches/patch_faces.h).
#include "common/patches/patch_faces.h"

#include <algorithm>
#include <cmath>

namespace firstshot {
namespace {

/// Barycentric coordinates (β, γ) of @p p, projected onto the plane of triangle (a, b, c), so that
/// p ≈ a + β(b − a) + γ(c − a); (−1, −1) for a degenerate triangle.
Vec2d barycentric(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& p) {
  const Vec3d e1 = b - a, e2 = c - a, d = p - a;
  const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const double p1 = glm::dot(d, e1), p2 = glm::dot(d, e2), det = d11 * d22 - d12 * d12;
  if (!(det > 0.0)) return Vec2d(-1.0);
  return Vec2d(d22 * p1 - d12 * p2, d11 * p2 - d12 * p1) / det;
}

/// How far @p p lies outside face @p f, relative to its size: 0 inside (and in its plane).
double outside(const ShapeDesc& s, const Face& f, const Vec3d& p) {
  const FaceTriangle t = faceTriangle(s, f, p);
  const Vec3d& a = s.vertices[f.v[0]];
  const Vec3d& b = s.vertices[f.v[t.corner[1]]];
  const Vec3d& c = s.vertices[f.v[t.corner[2]]];
  const Vec3d n = glm::cross(b - a, c - a);
  const double size = std::max(glm::length(b - a), glm::length(c - a));
  const double plane = glm::length(n) > 0.0 && size > 0.0 ? std::abs(glm::dot(p - a, glm::normalize(n))) / size : 1.0;
  return std::max({-t.bary.x, -t.bary.y, t.bary.x + t.bary.y - 1.0, plane, 0.0});
}

}  // namespace

FaceTriangle faceTriangle(const ShapeDesc& s, const Face& f, const Vec3d& p) {
  const auto v = [&](int k) { return s.vertices[f.v[k]]; };
  FaceTriangle t;
  t.bary = barycentric(v(0), v(1), v(2), p);
  if (f.count == 4 && t.bary.x < 0.0) {
    t.corner[1] = 2, t.corner[2] = 3;
    t.bary = barycentric(v(0), v(2), v(3), p);
  }
  return t;
}

std::vector<uint32_t> mapPatchesToFaces(const SceneDesc& scene, const PatchMesh& mesh,
                                        const std::function<bool(const Patch&)>& wanted) {
  std::vector<uint32_t> face(mesh.size(), kNoFace);
  uint32_t lastShape = kNoFace, lastFace = 0;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    if (!wanted(p)) continue;
    const ShapeDesc& s = scene.shapes[p.shape];
    const uint32_t faces = uint32_t(s.faces.size());
    uint32_t start = p.shape == lastShape && lastFace < faces ? lastFace : 0, best = start;
    double bestOutside = 1e300;
    for (uint32_t k = 0; k < faces && bestOutside > 1e-4; ++k) {
      const uint32_t f = (start + k) % faces;
      const double d = outside(s, s.faces[f], Vec3d(p.centroid));
      if (d < bestOutside) bestOutside = d, best = f;
    }
    face[j] = best;
    lastShape = p.shape, lastFace = best;
  }
  return face;
}

}  // namespace firstshot
