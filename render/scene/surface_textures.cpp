// Base-colour textures on the traced patches: patch-to-face mapping, texture coordinates, albedo
// (render/scene/surface_textures.h).
#include "render/scene/surface_textures.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "common/texture.h"

namespace fs {
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

/// The triangle of face @p f that holds @p p: corners (0, 1, 2), or (0, 2, 3) of a quad when p lies beyond the
/// diagonal 0–2, with p's barycentric coordinates in it.
struct FaceTriangle {
  int corner[3] = {0, 1, 2};
  Vec2d bary{0.0};
};
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

/// Points and area weights of an n × n stratified set over patch @p p: a quad's bilinear grid (weighted by the
/// Jacobian), a triangle's folded square grid (equal weights).
template <typename F>
void forEachPatchPoint(const Patch& p, int n, const F& visit) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const float s = (float(i) + 0.5f) / float(n), t = (float(j) + 0.5f) / float(n);
      if (p.count == 4) {
        const Vec3 ds = (1.0f - t) * (p.v[1] - p.v[0]) + t * (p.v[2] - p.v[3]);
        const Vec3 dt = (1.0f - s) * (p.v[3] - p.v[0]) + s * (p.v[2] - p.v[1]);
        const Vec3 x = (1.0f - t) * ((1.0f - s) * p.v[0] + s * p.v[1]) + t * ((1.0f - s) * p.v[3] + s * p.v[2]);
        visit(x, double(glm::length(glm::cross(ds, dt))));
      } else {
        const float a = s + t > 1.0f ? 1.0f - s : s, b = s + t > 1.0f ? 1.0f - t : t;
        visit(p.v[0] + a * (p.v[1] - p.v[0]) + b * (p.v[2] - p.v[0]), 1.0);
      }
    }
}

}  // namespace

SurfaceTextures::SurfaceTextures(const SceneDesc& scene, const PatchMesh& mesh) : scene_(&scene), mesh_(&mesh) {
  const bool any = std::any_of(scene.materials.begin(), scene.materials.end(),
                               [](const MaterialDesc& m) { return m.hasTextures(); });
  if (!any) return;
  face_.assign(mesh.size(), kNoFace);
  uint32_t lastShape = kNoFace, lastFace = 0;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    if (!scene.materials[p.material].hasTextures()) continue;
    const ShapeDesc& s = scene.shapes[p.shape];
    const uint32_t faces = uint32_t(s.faces.size());
    uint32_t start = p.shape == lastShape && lastFace < faces ? lastFace : 0, best = start;
    double bestOutside = 1e300;
    for (uint32_t k = 0; k < faces && bestOutside > 1e-4; ++k) {
      const uint32_t f = (start + k) % faces;
      const double d = outside(s, s.faces[f], Vec3d(p.centroid));
      if (d < bestOutside) bestOutside = d, best = f;
    }
    face_[j] = best;
    lastShape = p.shape, lastFace = best;
  }
  patchSurface_.assign(mesh.size(), SurfacePoint{});
  tbb::parallel_for(uint32_t(0), mesh.size(), [&](uint32_t j) {
    if (face_[j] == kNoFace) return;
    Vec3d sum(0.0);
    double metallic = 0.0, roughness = 0.0, weight = 0.0;
    forEachPatchPoint(mesh.patches[j], 8, [&](const Vec3& x, double w) {
      const SurfacePoint s = at(j, x);
      sum += w * Vec3d(s.albedo);
      metallic += w * s.metallic, roughness += w * s.roughness;
      weight += w;
    });
    patchSurface_[j] = weight > 0.0 ? SurfacePoint{Color(sum / weight), float(metallic / weight), float(roughness / weight)}
                                    : at(j, mesh.patches[j].centroid);
  });
}

Vec2 SurfaceTextures::uvAt(uint32_t patch, const Vec3& p) const {
  const ShapeDesc& s = scene_->shapes[mesh_->patches[patch].shape];
  if (!s.hasUv()) return Vec2(0.0f);
  const uint32_t f = face_[patch];
  const FaceTriangle t = faceTriangle(s, s.faces[f], Vec3d(p));
  const Vec2 a = s.cornerUv(f, 0), b = s.cornerUv(f, t.corner[1]), c = s.cornerUv(f, t.corner[2]);
  return a + float(t.bary.x) * (b - a) + float(t.bary.y) * (c - a);
}

SurfacePoint SurfaceTextures::at(uint32_t patch, const Vec3& p) const {
  const Patch& q = mesh_->patches[patch];
  const MaterialDesc& m = scene_->materials[q.material];
  const bool hasUv = scene_->shapes[q.shape].hasUv();
  const Vec2 uv = hasUv ? uvAt(patch, p) : Vec2(0.0f);
  // Texels above 1 (float images) are clamped: a base colour is a reflectance (energy is conserved as the
  // factor's checks in validateScene say), metallic and roughness are fractions.
  const auto texel = [&](const Texture& t) {
    return glm::clamp(hasUv ? t.lookup(uv) : t.image->mean, Color(0.0f), Color(1.0f));
  };
  SurfacePoint s{m.albedo, m.metallic, m.roughness};
  if (m.albedoTexture) s.albedo *= texel(*m.albedoTexture);
  if (m.metallicRoughnessTexture) {
    const Color mr = texel(*m.metallicRoughnessTexture);
    s.roughness *= mr.y, s.metallic *= mr.z;
  }
  return s;
}

}  // namespace fs
