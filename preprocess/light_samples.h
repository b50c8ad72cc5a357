#pragma once
/// @file light_samples.h
/// The light samples the small lights (common/lights/small_light_rule.h) become: one per point, spot or
/// directional light, one per vertex of an area light's tessellation, one or twelve isotropic points
/// inside an emissive sphere (preprocess/sphere_light.h).
#include <cstdint>
#include <vector>

#include "common/lights/small_light_rule.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"

namespace firstshot {

/// The light samples of the given lights, in light order. An area light's emissive faces are split
/// into triangles (preprocess/light_tessellation.h): with edges at most @p lightPatchSize long (m) if
/// it is > 0, else automatically for relative accuracy @p lightTolerance of the vertex rule at the
/// receivers. Each shared vertex becomes one sample with the trapezoidal weight S_i/3 (S_i = area of
/// the triangles around it, m²) and the area-weighted normal of those triangles; an emissive mesh's
/// samples are then merged as its receivers allow (preprocess/light_clusters.h), and an emissive
/// sphere's are points inside it where they do (automatic only: preprocess/sphere_light.h). Progress over the
/// area lights' faces on stderr unless @p quiet.
std::vector<LightSample> makeLightSamples(const SceneDesc& scene, const std::vector<uint32_t>& lights,
                                          double lightPatchSize, double lightTolerance, bool quiet = true);

}  // namespace firstshot
