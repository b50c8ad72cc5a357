#pragma once
/// @file patch_size.h
/// The coarse patch size of a scene that does not set `patch_size`: taken from the scene's own
/// geometry, not from a length, so that a scene modelled in millimetres, metres or kilometres gets
/// the same patches. Cutting the faces to that size (the uniform mesh, common/patches/patches.h) adds at most
/// kAutoPatchBudget patches to the faces themselves: faces longer than it are split, shorter ones
/// are taken as they are, so a scene of a million small triangles still gets its walls split while
/// a plain room gets about kAutoPatchBudget patches. Adaptive refinement then splits the patches that
/// shadows cross (preprocess/adaptive_mesh.h), down to 1/16 of the size.
#include "common/scene/scene_desc.h"

namespace firstshot {

/// Patches the automatic size may add to the scene's faces (docs/firstshot-format.md, "Patch size").
inline constexpr double kAutoPatchBudget = 16384;

/// The largest edge length h (m) whose uniform mesh has at most @p budget patches more than the
/// scene has faces: countPatchPolygons(scene, h) ≤ countPatchPolygons(scene, kFacesAsTheyAre) + budget.
/// A pure function of the geometry's shape: scaling the scene by s scales the result by s.
double autoPatchSize(const SceneDesc& scene, double budget = kAutoPatchBudget);

/// minPatchSize when neither the scene nor the command line gives one: patchSize / this (adaptive
/// refinement by up to log2 of it levels; docs/firstshot-format.md, "Contacts").
inline constexpr double kDefaultRefineRatio = 16.0;

/// Replaces the automatic patch sizes of @p settings by their values, the one place they are resolved
/// (called by preprocess/preprocessor.h's resolveSettings and preprocessScene):
///   patchSize ≤ 0: autoPatchSize(scene);
///   minPatchSize ≤ 0: patchSize / kDefaultRefineRatio; above patchSize: patchSize (a uniform mesh).
/// Idempotent: resolved settings come back as they are.
void resolvePatchSizes(const SceneDesc& scene, FirstShotSettings& settings);

/// The coarse patch size of the scene's own settings, resolved as resolvePatchSizes does:
/// scene.settings.patchSize when the scene gives one, else autoPatchSize(). For the renderer without
/// a table (--integrator bundle) and tests.
double resolvePatchSize(const SceneDesc& scene);

}  // namespace firstshot
