// RenderScene: the immutable scene an integrator reads, and the check that a first-shot table
// belongs to it.
#include "render/scene/render_scene.h"

#include <string>

#include "common/util/error.h"
#include "render/scene/table_rows.h"

namespace firstshot {

RenderScene::RenderScene(SceneDesc scene, double patchSize) : desc_(std::move(scene)) {
  // Without a table nothing needs patches smaller than the faces (the bundle integrator's elements
  // are the exception; its caller passes a size): every face is traced as it is.
  mesh_ = buildPatches(desc_, patchSize > 0 ? patchSize : kFacesAsTheyAre);
  build({});
}

RenderScene::RenderScene(SceneDesc scene, FirstShotTable table, const std::string& tablePath)
    : desc_(std::move(scene)), table_(std::move(table)) {
  const FirstShotTable& t = *table_;
  const std::string& file = tablePath.empty() ? std::string("first-shot table") : tablePath;
  auto fail = [&](const char* section, const std::string& msg) { throw InputError(file, section, msg); };
  const uint64_t sceneHash = hashScene(desc_);
  if (t.sceneHash != sceneHash)
    fail("header", "made for a different scene (the scene's geometry, materials or lights changed): run firstshot-preprocess again");
  if (const char* wrong = TableRows::check(t)) fail("factors", wrong);
  for (const LightSample& s : t.samples)
    if (s.light >= desc_.lights.size()) fail("samples", "a light sample refers to a light the scene does not have");
  for (uint32_t l : t.replacedLights)
    if (l >= desc_.lights.size()) fail("lights", "a replaced light index is out of range for this scene");
  for (const Patch& p : t.mesh.patches)
    if (p.material >= desc_.materials.size() || p.shape >= desc_.shapes.size())
      fail("patches", "a patch refers to a material or shape the scene does not have");
  for (const Luminaire& lum : t.luminaires)
    for (uint32_t l : lum.lights)
      if (l >= desc_.lights.size() || desc_.lights[l].type == LightType::Directional)
        fail("luminaires", "luminaire \"" + lum.name + "\" holds a light this scene does not have there");
  build(t.replacedLights);
}

void RenderScene::build(const std::vector<uint32_t>& replaced) {
  bsdfs_.reserve(desc_.materials.size());
  for (const MaterialDesc& m : desc_.materials) bsdfs_.push_back(makeBSDF(m));
  lights_ = LightSet(desc_, replaced);
  if (table_) luminaires_ = LuminaireBoxes(&table_->luminaires, lights_);
  patchMaterial_.reserve(mesh().size());
  for (const Patch& p : mesh().patches) patchMaterial_.push_back(p.material);
  textures_ = SurfaceTextures(desc_, mesh());
  shading_ = ShadingNormals(desc_, mesh());  // nothing without mesh normals or normal maps
  if (!textures_.empty()) {
    patchBsdfs_.reserve(mesh().size());
    for (uint32_t j = 0; j < mesh().size(); ++j) {
      if (!textures_.textured(j)) {
        patchBsdfs_.push_back(bsdfs_[patchMaterial_[j]]);
        continue;
      }
      const SurfacePoint& s = textures_.patchSurface(j);
      patchBsdfs_.push_back(makeBSDF(desc_.materials[patchMaterial_[j]], s.albedo, s.metallic, s.roughness));
    }
  }
  for (const RenderLight& l : lights_.lights())
    if (l.type == LightType::Area) {
      if (emitterMaterial_.size() <= l.emitter) emitterMaterial_.resize(l.emitter + 1);
      emitterMaterial_[l.emitter] = static_cast<uint32_t>(desc_.shapes[size_t(l.desc.shape)].material);
    }
  // Thin glass panes: the patches shadow rays see through (EmbreeScene::transmittance).
  GlassPatches glass;
  std::vector<uint16_t> paneOfMaterial(bsdfs_.size(), 0);
  for (size_t m = 0; m < bsdfs_.size(); ++m)
    if (const ThinGlassBSDF* g = bsdfs_[m].thinGlass()) {
      glass.panes.push_back(*g);
      paneOfMaterial[m] = static_cast<uint16_t>(glass.panes.size());
    }
  if (!glass.empty()) {
    glass.paneOfPatch.reserve(patchMaterial_.size());
    for (uint32_t m : patchMaterial_) glass.paneOfPatch.push_back(paneOfMaterial[m]);
  }
  cutouts_ = PatchCutouts::build(desc_, mesh());  // alpha cut-outs: null for a scene without
  // Where the patches far outnumber the faces (a table's, the bundle's), the faces are traced and a locator finds
  // each hit's patch (render/scene/patch_locator.h); not with cut-outs, whose filter works by patch.
  std::shared_ptr<const PatchLocator> locator;
  if (!cutouts_) locator = PatchLocator::build(desc_, mesh());
  embree_ = std::make_unique<EmbreeScene>(mesh(), lights_.emitterMeshes(), std::move(glass), cutouts_, std::move(locator));
}

}  // namespace firstshot
