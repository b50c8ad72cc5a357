// Alpha cut-outs on the patch mesh: validation, the blend mode's coin, patch-to-face mapping and alpha lookups
// (common/patches/patch_cutouts.h).
#include "common/patches/patch_cutouts.h"

#include <algorithm>
#include <cmath>

#include "common/materials/texture.h"
#include "common/patches/patch_faces.h"
#include "common/util/error.h"
#include "common/util/hash.h"

namespace firstshot {

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
  c->face_ = mapPatchesToFaces(scene, mesh, [&](const Patch& p) { return scene.materials[p.material].isCutout(); });
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
  uv = faceTriangle(s, s.faces[f], p).interpolate<Vec2>([&](int k) { return s.cornerUv(f, k); });
  return true;
}

}  // namespace firstshot
