// Alpha cut-outs on the patch mesh: validation, the blend mode's coin, patch-to-face mapping and alpha lookups
// (common/patch_cutouts.h).
#include "common/patch_cutouts.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/hash.h"
#include "common/texture.h"

namespace fs {
namespace {

/// Barycentric coordinates (β, γ) of @p p in triangle (a, b, c), projected onto its plane; (−1, −1) if degenerate.
Vec2d cutoutBarycentric(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& p) {
  const Vec3d e1 = b - a, e2 = c - a, d = p - a;
  const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const double p1 = glm::dot(d, e1), p2 = glm::dot(d, e2), det = d11 * d22 - d12 * d12;
  if (!(det > 0.0)) return Vec2d(-1.0);
  return Vec2d(d22 * p1 - d12 * p2, d11 * p2 - d12 * p1) / det;
}

/// The corners (0, k1, k2) of the triangle of face @p f holding @p p (a quad: (0, 1, 2) or (0, 2, 3)) and p's
/// barycentric coordinates in it.
struct CutoutTriangle {
  int k1 = 1, k2 = 2;
  Vec2d bary{0.0};
};
CutoutTriangle cutoutTriangle(const ShapeDesc& s, const Face& f, const Vec3d& p) {
  CutoutTriangle t;
  t.bary = cutoutBarycentric(s.vertices[f.v[0]], s.vertices[f.v[1]], s.vertices[f.v[2]], p);
  if (f.count == 4 && t.bary.x < 0.0) {
    t.k1 = 2, t.k2 = 3;
    t.bary = cutoutBarycentric(s.vertices[f.v[0]], s.vertices[f.v[2]], s.vertices[f.v[3]], p);
  }
  return t;
}

/// How far @p p lies outside face @p f (relative to its size; 0 inside and in its plane).
double cutoutOutside(const ShapeDesc& s, const Face& f, const Vec3d& p) {
  const CutoutTriangle t = cutoutTriangle(s, f, p);
  const Vec3d &a = s.vertices[f.v[0]], &b = s.vertices[f.v[t.k1]], &c = s.vertices[f.v[t.k2]];
  const Vec3d n = glm::cross(b - a, c - a);
  const double size = std::max(glm::length(b - a), glm::length(c - a));
  const double plane = glm::length(n) > 0.0 && size > 0.0 ? std::abs(glm::dot(p - a, glm::normalize(n))) / size : 1.0;
  return std::max({-t.bary.x, -t.bary.y, t.bary.x + t.bary.y - 1.0, plane, 0.0});
}

}  // namespace

void validateCutout(const std::string& file, const std::string& where, const MaterialDesc& m) {
  if (!(m.alphaCutoff >= 0.0f && m.alphaCutoff <= 1.0f)) throw InputError(file, where + ".alpha_cutoff", "must be in [0, 1]");
  if (!(m.alpha >= 0.0f && m.alpha <= 1.0f)) throw InputError(file, where + ".alpha", "must be in [0, 1]");
  if (!m.isCutout()) return;
  if (m.type != MaterialType::Diffuse && m.type != MaterialType::Glossy && m.type != MaterialType::Pbr)
    throw InputError(file, where + ".alpha_mode", "cut-outs apply to diffuse, glossy and pbr materials");
  if (m.isEmissive()) throw InputError(file, where + ".alpha_mode", "an emitting surface cannot be a cut-out");
}

uint64_t cutoutKey(const Vec3& o, const Vec3& d, uint32_t patch) {
  Hasher h;
  h.add(o).add(d).add(patch);
  return h.value();
}

bool surfaceExists(const MaterialDesc& m, float alpha, uint64_t key) {
  switch (m.alphaMode) {
    case AlphaMode::Opaque: return true;
    case AlphaMode::Mask: return alpha >= m.alphaCutoff;
    case AlphaMode::Blend: return double(key >> 11) * 0x1.0p-53 < double(alpha);
  }
  return true;
}

std::shared_ptr<const PatchCutouts> PatchCutouts::build(const SceneDesc& scene, const PatchMesh& mesh) {
  if (std::none_of(scene.materials.begin(), scene.materials.end(), [](const MaterialDesc& m) { return m.isCutout(); }))
    return nullptr;
  auto c = std::make_shared<PatchCutouts>();
  c->scene_ = &scene;
  c->mesh_ = &mesh;
  c->meanAlpha_.assign(scene.materials.size(), 1.0f);
  for (size_t k = 0; k < scene.materials.size(); ++k) {
    const MaterialDesc& m = scene.materials[k];
    double a = 1.0;
    if (m.alphaTexture) {
      const TexelImage& im = *m.alphaTexture->image;
      double sum = 0.0;
      if (im.alpha.empty())
        for (const Color& t : im.texels) sum += t.x;
      else
        for (float t : im.alpha) sum += t;
      a = im.texels.empty() ? 1.0 : sum / double(im.texels.size());
    }
    c->meanAlpha_[k] = float(std::clamp(double(m.alpha) * a, 0.0, 1.0));
  }
  c->face_.assign(mesh.size(), kNoFace);
  uint32_t lastShape = kNoFace, lastFace = 0;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    if (!scene.materials[p.material].isCutout()) continue;
    const ShapeDesc& s = scene.shapes[p.shape];
    const uint32_t faces = uint32_t(s.faces.size());
    const uint32_t start = p.shape == lastShape && lastFace < faces ? lastFace : 0;
    uint32_t best = start;
    double bestOutside = 1e300;
    for (uint32_t k = 0; k < faces && bestOutside > 1e-4; ++k) {
      const uint32_t f = (start + k) % faces;
      const double d = cutoutOutside(s, s.faces[f], Vec3d(p.centroid));
      if (d < bestOutside) bestOutside = d, best = f;
    }
    c->face_[j] = best;
    lastShape = p.shape, lastFace = best;
  }
  return c;
}

float PatchCutouts::coverage(uint32_t patch, const Vec3d& p) const {
  if (!cutout(patch)) return 1.0f;
  const MaterialDesc& m = scene_->materials[mesh_->patches[patch].material];
  const float a = alphaAt(patch, p);
  return m.alphaMode == AlphaMode::Blend ? a : m.alphaMode == AlphaMode::Mask && a < m.alphaCutoff ? 0.0f : 1.0f;
}

float PatchCutouts::alphaAt(uint32_t patch, const Vec3d& p) const {
  const MaterialDesc& m = scene_->materials[mesh_->patches[patch].material];
  Vec2 uv;
  if (!uvAt(patch, p, uv)) return meanAlpha_[mesh_->patches[patch].material];
  return std::clamp(m.alpha * m.alphaTexture->alphaLookup(uv), 0.0f, 1.0f);
}

bool PatchCutouts::uvAt(uint32_t patch, const Vec3d& p, Vec2& uv) const {
  const Patch& q = mesh_->patches[patch];
  const ShapeDesc& s = scene_->shapes[q.shape];
  if (!scene_->materials[q.material].alphaTexture || !s.hasUv() || face_[patch] == kNoFace) return false;
  const uint32_t f = face_[patch];
  const CutoutTriangle t = cutoutTriangle(s, s.faces[f], p);
  const Vec2 a = s.cornerUv(f, 0), b = s.cornerUv(f, t.k1), c = s.cornerUv(f, t.k2);
  uv = a + float(t.bary.x) * (b - a) + float(t.bary.y) * (c - a);
  return true;
}

}  // namespace fs
