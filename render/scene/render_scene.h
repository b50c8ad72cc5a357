#pragma once
/// @file render_scene.h
/// Everything an integrator reads, immutable once built: the scene description, the patch mesh
/// that is traced (the first-shot table's own mesh when one is given, so a hit's primitive is the
/// table's patch ID), one BSDF per material, the lights, and the optional first-shot table.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/materials/bsdf.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "render/scene/embree_scene.h"
#include "render/scene/light_set.h"
#include "render/scene/luminaire_boxes.h"
#include "render/scene/ray.h"
#include "render/scene/scene_memo.h"
#include "render/scene/shading_normals.h"
#include "render/scene/surface_textures.h"

namespace firstshot {

class RenderScene {
 public:
  /// A scene without first-shot: traces buildPatches(scene, patchSize), or every face as it is
  /// (one patch per face) when @p patchSize <= 0. Every light is sampled by the integrator.
  explicit RenderScene(SceneDesc scene, double patchSize = 0);

  /// A scene with a first-shot table: traces the table's patch mesh; the table's replacedLights
  /// leave light sampling. @p tablePath names the table in error messages.
  /// @throws InputError if the table does not belong to the scene (scene hash, light and
  ///         material indices, sizes).
  RenderScene(SceneDesc scene, FirstShotTable table, const std::string& tablePath = "");

  RenderScene(const RenderScene&) = delete;
  RenderScene& operator=(const RenderScene&) = delete;

  const SceneDesc& desc() const { return desc_; }
  const PatchMesh& mesh() const { return table_ ? table_->mesh : mesh_; }
  const LightSet& lights() const { return lights_; }
  /// The table's luminaires (render/scene/luminaire_boxes.h); empty without a table or without luminaires in it.
  const LuminaireBoxes& luminaires() const { return luminaires_; }
  /// The first-shot table, or nullptr.
  const FirstShotTable* firstShot() const { return table_ ? &*table_ : nullptr; }
  /// The BSDF of material @p m (without its texture: see bsdfAt).
  const BSDF& bsdf(uint32_t m) const { return bsdfs_[m]; }
  /// The BSDF at @p hit: its material's, with its textures (base colour, metallic-roughness) looked up at the
  /// hit point when it has some (the one place integrators get a surface's BSDF from).
  /// A point with a shading normal (shadingNormal) gets a BSDF that knows the geometric normal in the shading
  /// frame (BSDF::setGeometricNormal): integrators evaluate and sample it in shadingFrame(hit).
  BSDF bsdfAt(const Hit& hit) const {
    BSDF b = texturedBsdf(hit);
    if (!shading_.empty() && hit.onPatch() && shading_.shaded(hit.patch)) {
      const Vec3 ns = shading_.normalAt(hit.patch, hit.p, hit.ng);
      if (ns != hit.ng) b.setGeometricNormal(Frame(ns).toLocal(hit.ng));
    }
    return b;
  }
  // --- Shading normals (render/scene/shading_normals.h) ---
  /// The unit shading normal at @p hit, on the front side of hit.ng: the source face's corner normals
  /// interpolated, perturbed by the material's normal map; hit.ng itself (the same bits) where there are none.
  Vec3 shadingNormal(const Hit& hit) const {
    if (shading_.empty() || !hit.onPatch() || !shading_.shaded(hit.patch)) return hit.ng;
    return shading_.normalAt(hit.patch, hit.p, hit.ng);
  }
  /// The frame BSDFs are evaluated in at @p hit: about shadingNormal(hit) (Frame(hit.ng) without shading normals).
  Frame shadingFrame(const Hit& hit) const { return Frame(shadingNormal(hit)); }
  /// The shading normals on the patches (empty when the scene has none).
  const ShadingNormals& shadingNormals() const { return shading_; }
  /// The BSDF of patch @p j as a whole, its texture averaged over the patch: for what works per patch (the lit
  /// patches as emitters, render/firstshot/patch_emitters.h).
  const BSDF& patchBsdf(uint32_t j) const { return patchBsdfs_.empty() ? bsdfs_[patchMaterial_[j]] : patchBsdfs_[j]; }
  /// The textures on the patches (empty when the scene has none).
  const SurfaceTextures& textures() const { return textures_; }
  /// The material of a hit (patch or emitter).
  uint32_t material(const Hit& hit) const {
    return hit.onPatch() ? patchMaterial_[hit.patch] : emitterMaterial_[hit.emitter];
  }

  bool intersect(const Ray& ray, Hit& hit) const { return embree_->intersect(ray, hit); }
  bool occluded(const Ray& ray) const { return embree_->occluded(ray); }
  /// What crosses the segment: 0 when an opaque surface blocks it, else the product of the thin glass
  /// panes' T(θ) along it (EmbreeScene::transmittance; occluded() for a scene without glass). Every shadow
  /// ray of render/ asks this.
  Color transmittance(const Ray& ray) const { return embree_->transmittance(ray); }
  const EmbreeScene& embree() const { return *embree_; }
  /// The alpha cut-outs on the traced mesh, or nullptr when the scene has none (common/patches/patch_cutouts.h).
  const PatchCutouts* cutouts() const { return cutouts_.get(); }
  /// Products derived from this scene that integrators share once built (render/scene/scene_memo.h): a cache,
  /// so a const scene may fill it.
  SceneMemo& memo() const { return memo_; }

 private:
  void build(const std::vector<uint32_t>& replaced);
  /// The BSDF at @p hit with its textures, before shading normals.
  BSDF texturedBsdf(const Hit& hit) const {
    const uint32_t m = material(hit);
    if (textures_.empty() || !hit.onPatch() || !textures_.textured(hit.patch)) return bsdfs_[m];
    const SurfacePoint s = textures_.at(hit.patch, hit.p);
    return makeBSDF(desc_.materials[m], s.albedo, s.metallic, s.roughness);
  }

  SceneDesc desc_;
  std::optional<FirstShotTable> table_;
  PatchMesh mesh_;  ///< used when there is no table
  std::vector<BSDF> bsdfs_;
  std::vector<uint32_t> patchMaterial_;  ///< by patch: a compact copy of Patch::material for the hot path
  std::vector<uint32_t> emitterMaterial_;
  SurfaceTextures textures_;
  ShadingNormals shading_;  ///< per-patch shading normals
  std::vector<BSDF> patchBsdfs_;  ///< by patch, when the scene has textures
  LightSet lights_;
  LuminaireBoxes luminaires_;
  std::shared_ptr<const PatchCutouts> cutouts_;  ///< alpha cut-outs on the traced mesh (null: none)
  std::unique_ptr<EmbreeScene> embree_;
  mutable SceneMemo memo_;
};

}  // namespace firstshot
