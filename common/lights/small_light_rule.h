#pragma once
/// @file small_light_rule.h
/// Which lights first-shot replaces ("small") and which stay in the renderer ("large"): the rule
/// of docs/scene-format.md, shared by the preprocessor and by integrators that run without a table.
#include <cstdint>
#include <vector>

#include "common/scene/scene_desc.h"

namespace firstshot {

/// Solid angle (sr) an area light subtends from the centre of the scene's bounding box; 0 for
/// point, spot and directional lights (they have no extent).
double lightSolidAngleFromCentre(const SceneDesc& scene, const LightDesc& light);

/// A light is small when its "small" key says true; large when it says false; with "auto" (the
/// default) point, spot and directional lights are small, and an area light is small when it
/// subtends at most @p maxSolidAngle steradians from the centre of the scene's bounds (Ward: 1 sr).
bool isSmallLight(const SceneDesc& scene, const LightDesc& light, double maxSolidAngle);

/// Indices into scene.lights of the small lights, ascending.
std::vector<uint32_t> smallLights(const SceneDesc& scene, double maxSolidAngle);

}  // namespace firstshot
