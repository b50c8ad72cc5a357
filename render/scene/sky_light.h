#pragma once
/// @file sky_light.h
/// The scene's infinite light: its sky model baked into a lat-long EnvironmentMap, or its environment
/// map file read, as the one infinitely distant, large light of the render scene (LightSet::environment). It is
/// never replaced by a first-shot table: NEE samples it by the map's importance density, paths that escape the
/// scene meet it (power-heuristic MIS between the two), camera rays that escape see it as the background.
///
/// Baking a sky (common/scene/sky_desc.h): texel (i, j) of a W × H map (the mapping of environment_map.h) holds the mean
/// radiance over its solid angle, from a kSub × kSub grid of points equally spaced in cos θ and azimuth (equal solid
/// angles); rows below the horizon (H is even, so the horizon is a texel edge) hold the ground's luminance. All in
/// the renderer's radiance, luminance / photometry::kEfficacy on every channel. At the default 256 × 128 (1.4° texels;
/// under 1 MB: at 512 × 256 sky-courtyard took 1.5× the CPU time, mostly cache misses in the map's sampling) the
/// map's horizontal illuminance is the model's within 0.5% (tests/test_sky_light.cpp). Camera rays and rays after a
/// mirror see the model itself (LightSet::background), not the texels.
#include <memory>

#include "common/scene/scene_desc.h"
#include "common/scene/sky_desc.h"
#include "render/scene/environment_map.h"

namespace firstshot {

/// The sky @p sky as a lat-long map of @p width × @p height texels (@p height even).
EnvironmentMap bakeSky(const SkyDesc& sky, int width = 256, int height = 128);

/// The infinite light of @p scene: its sky baked, or its environment file read (scaled, rotated); null if it has
/// neither. @throws InputError naming the scene file and "environment.file" if the image cannot be read.
std::shared_ptr<const EnvironmentMap> makeInfiniteLight(const SceneDesc& scene);

}  // namespace firstshot
