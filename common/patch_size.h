#pragma once
/// @file patch_size.h
/// The coarse patch size of a scene that does not set `patch_size`: taken from the scene's own
/// geometry, not from a length, so that a scene modelled in millimetres, metres or kilometres gets
/// the same patches. Cutting the faces to that size (the uniform mesh, common/patches.h) adds at most
/// kAutoPatchBudget patches to the faces themselves: faces longer than it are split, shorter ones
/// are taken as they are, so a scene of a million small triangles still gets its walls split while
/// a plain room gets about kAutoPatchBudget patches. Adaptive refinement then splits the patches that
/// shadows cross (preprocess/adaptive_mesh.h), down to 1/16 of the size.
#include "common/scene_desc.h"

namespace fs {

/// Patches the automatic size may add to the scene's faces (docs/firstshot-format.md, "Patch size").
inline constexpr double kAutoPatchBudget = 16384;

/// The largest edge length h (m) whose uniform mesh has at most @p budget patches more than the
/// scene has faces: countPatchPolygons(scene, h) ≤ countPatchPolygons(scene, kFacesAsTheyAre) + budget.
/// A pure function of the geometry's shape: scaling the scene by s scales the result by s.
double autoPatchSize(const SceneDesc& scene, double budget = kAutoPatchBudget);

/// settings.patchSize when the scene (or a command line, written into it) gives one, else autoPatchSize().
double resolvePatchSize(const SceneDesc& scene);

}  // namespace fs
