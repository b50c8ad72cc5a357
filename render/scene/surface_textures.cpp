// Base-colour textures on the traced patches: patch-to-face mapping, texture coordinates, albedo
// (render/scene/surface_textures.h).
#include "render/scene/surface_textures.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "common/materials/texture.h"

namespace firstshot {
namespace {

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
  face_ = mapPatchesToFaces(scene, mesh, [&](const Patch& p) { return scene.materials[p.material].hasTextures(); });
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
  return faceTriangle(s, s.faces[f], Vec3d(p)).interpolate<Vec2>([&](int k) { return s.cornerUv(f, k); });
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

}  // namespace firstshot
