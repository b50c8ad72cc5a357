#pragma once
/// @file patch_emitters.h
/// The lit first-shot patches as light sources: what every user of them (next-event estimation in
/// render/lights/next_event.h, the light subpaths of bidirectional path tracing in EmissionSampler) needs to
/// know about one patch side as an emitter.
///
/// Side s of patch j (s = 0: the side its normal faces) sends the first-shot radiance
/// Σ_i e_i r_ij f_r(ω'_i, y, ω) of FirstShotLighting into its half-space; its power is about
/// albedo · E_js · A_j, the weight with which emitters are chosen (any positive weight keeps the
/// estimators unbiased: they divide by the probability they used). A textured patch's power takes the
/// albedo averaged over the patch (RenderScene::patchBsdf); its radiance at a point, the texture there.
///
/// A polished point (BSDF::tooSharpForTable: pbr below roughness 0.3) emits nothing: the table's patch-level
/// sum cannot follow its lobe, and every integrator takes the replaced lights' reflection there from the
/// lights themselves (the path walk's NEE to every light, the shooting integrators' polished-first particles
/// and camera-side NEE: docs/light-tracing.md, docs/bdpt.md). A patch whose material is polished everywhere
/// has no power.
#include "common/patches/patches.h"
#include "render/firstshot/lighting.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// A uniform point (by area) of a planar triangle or convex quad patch, from @p u ∈ [0,1)².
Vec3 samplePatchPoint(const Patch& p, Vec2 u);

/// Power that side @p side of patch @p j re-emits, channel mean, W: albedo · E · A with E the
/// side's first-shot irradiance (@p sideIrradiance = FirstShotTable::sideIrradiance()). 0 for
/// delta BSDFs (mirrors and glass reflect no first-shot term) and polished materials.
float patchSidePower(const RenderScene& scene, const std::vector<Color>& sideIrradiance, uint32_t j, uint32_t side);

/// Whether a point of @p scene may be polished (BSDF::tooSharpForTable): a pbr material below the table's
/// roughness, or one with a metallic-roughness texture (which scales the roughness down).
bool mayBePolished(const RenderScene& scene);

/// The coverage of point @p y of patch @p j (PatchCutouts::coverage; 1 without cut-outs): what a point sampled
/// on a patch emitter, rather than hit by a ray, multiplies its radiance by.
inline float cutoutCoverage(const RenderScene& scene, uint32_t j, const Vec3& y) {
  return scene.cutouts() ? scene.cutouts()->coverage(j, Vec3d(y)) : 1.0f;
}

/// Unit normal of side @p side of patch @p p (the direction it emits into).
inline Vec3 patchSideNormal(const Patch& p, uint32_t side) { return side == 0 ? p.normal : -p.normal; }

/// Whether a ray arriving at the point @p y of patch @p j along −@p w (@p w: the unit direction in which y
/// emits) meets patch @p j there: a probe ray from y + h·w back to y, h = 2·10⁻⁵ of the coordinates' magnitude
/// (at least 0.02 mm). False where another surface lies on y: a face coplanar with the patch (a stand's top
/// under a bowl's bottom), where the ray tracer returns one of the two by the ray's direction, or one less
/// than h from y along w. The estimators that meet patches by rays (the path walk reading the table at its
/// hits, BDPT's s = 0) never reach such a point from that direction, while a point sampled on the patch by
/// area (particles leaving lit patches, BDPT's s = 1, patch NEE) would emit from it through the covering
/// face; a sampled point emits only where this holds, so that every estimator has the same path space.
/// Costs one short ray.
bool patchPointExposed(const RenderScene& scene, uint32_t j, const Vec3& y, const Vec3& w);

/// What the radiance that a point @p y sampled by area on patch @p j (rather than met by a ray) sends in the
/// unit direction @p w is multiplied by: its cut-out coverage where patchPointExposed() holds, else 0
/// (dimensionless). Call it only for radiance that is not 0: it traces a ray.
inline float sampledPatchPointWeight(const RenderScene& scene, uint32_t j, const Vec3& y, const Vec3& w) {
  const float c = cutoutCoverage(scene, j, y);
  return c > 0.0f && patchPointExposed(scene, j, y, w) ? c : 0.0f;
}

/// First-shot radiance leaving the point @p y of patch @p j in the unit direction @p w, W/(m² sr)
/// (0 where that side sends nothing, and at a polished point). @p lighting must be built for @p scene.
Color patchRadiance(const RenderScene& scene, const FirstShotLighting& lighting, uint32_t j, const Vec3& y,
                    const Vec3& w);

}  // namespace firstshot
