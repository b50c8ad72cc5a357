#pragma once
/// @file light_samples.h
/// Which lights first-shot replaces ("small"), and the light samples they become: one per point,
/// spot or directional light, one per vertex of an area light's tessellation.
#include <cstdint>
#include <vector>

#include "common/firstshot.h"
#include "common/scene_desc.h"

namespace fs {

/// Solid angle (sr) an area light subtends from the centre of the scene's bounding box; 0 for
/// point, spot and directional lights (they have no extent).
double lightSolidAngleFromCentre(const SceneDesc& scene, const LightDesc& light);

/// The small-light rule (docs/scene-format.md): a light is small, and replaced by first-shot, when
/// its "small" key says true; large when it says false; with "auto" (the default) point, spot and
/// directional lights are small, and an area light is small when it subtends at most
/// @p maxSolidAngle steradians from the centre of the scene's bounds (Ward uses 1 sr).
bool isSmallLight(const SceneDesc& scene, const LightDesc& light, double maxSolidAngle);

/// Indices into scene.lights of the small lights, ascending.
std::vector<uint32_t> smallLights(const SceneDesc& scene, double maxSolidAngle);

/// The light samples of the given lights, in light order. An area light's emissive faces are split
/// into triangles with edges at most @p lightPatchSize long; each shared vertex becomes one sample
/// with the trapezoidal weight S_i/3 (S_i = area of the triangles around it) and the area-weighted
/// normal of those triangles.
std::vector<LightSample> makeLightSamples(const SceneDesc& scene, const std::vector<uint32_t>& lights,
                                          double lightPatchSize);

}  // namespace fs
