#pragma once
/// @file direct_light.h
/// Direct lighting shared by the integrators: next-event estimation (NEE) to the scene's lights.
/// The first-shot term of a table is render/firstshot/lighting.h (FirstShotLighting).
#include <cstdint>
#include <vector>

#include "common/bsdf.h"
#include "common/lights.h"
#include "common/math.h"
#include "common/rng.h"
#include "render/ray.h"
#include "render/render_scene.h"

namespace fs {

class FirstShotLighting;  // render/firstshot/lighting.h

/// Power heuristic (β = 2) weight of a technique with density @p a against one with density @p b.
inline float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

/// A shadow ray from the hit towards a light @p distance (m) away in direction @p wi: from the hit's
/// offset origin straight at that point (not parallel to @p wi), stopping eps + 1e-4·distance short
/// of it, since the light may be emitter geometry itself.
Ray shadowRay(const Hit& hit, const Vec3& wi, float distance);

/// Which lights estimateDirect() samples, and how it weights them.
struct DirectLightOptions {
  bool skipReplaced = false;  ///< leave out the small lights a first-shot table replaces
  /// If set: only lights l with (*include)[l] != 0 (indexed like LightSet::lights()).
  const std::vector<uint8_t>* include = nullptr;
  /// Area lights: power-heuristic weight against BSDF sampling (which must then count the
  /// emission it meets, with the complementary weight); false: weight 1 (BSDF sampling must not count them).
  bool mis = true;
  /// Integrate only f − ρd/π, the BSDF without its Lambertian part (the part an irradiance cache leaves out).
  bool nonDiffuseOnly = false;
  /// If set, at a hit on a patch: no shadow ray to a replaced light the table finds visible from the
  /// whole patch or from none of it (FirstShotLighting::visibility; --shadow-rays uncertain).
  const FirstShotLighting* tableVisibility = nullptr;
};

/// One NEE sample per selected light: Σ_l f·|cos θ_i|·L_l/pdf_l·weight, unoccluded samples only.
/// Takes two dimensions per light of the scene, selected or not (drawn for the selected ones only), so
/// later dimensions do not shift.
/// @p rays is incremented by the shadow rays traced.
Color estimateDirect(const RenderScene& scene, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                     const DirectLightOptions& options, Sampler& sampler, uint64_t& rays);

}  // namespace fs
