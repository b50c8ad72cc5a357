#pragma once
/// @file patch_size.h
/// The coarse patch size of a scene that does not set `patch_size`: taken from the scene's own
/// geometry, not from a length, so that a scene modelled in millimetres, metres or kilometres gets
/// the same patches. The uniform mesh of that size (common/patches.h) has at most
/// kDefaultPatchCount patches: faces longer than it are split, shorter ones are taken as they are
/// (a scene of more faces than that gets one patch per face). Adaptive refinement then splits the
/// patches that shadows cross (preprocess/adaptive_mesh.h), down to 1/16 of the size.
#include "common/scene_desc.h"

namespace fs {

/// Coarse patches the automatic size aims at (at most; see docs/firstshot-format.md, "Patch size").
inline constexpr double kDefaultPatchCount = 16384;

/// The largest edge length h (m) whose uniform mesh countPatchPolygons(scene, h) has at most
/// @p targetCount patches, or the longest edge of any face when even one patch per face exceeds it.
/// A pure function of the geometry's shape: scaling the scene by s scales the result by s.
double autoPatchSize(const SceneDesc& scene, double targetCount = kDefaultPatchCount);

/// settings.patchSize when the scene (or a command line, written into it) gives one, else autoPatchSize().
double resolvePatchSize(const SceneDesc& scene);

}  // namespace fs
