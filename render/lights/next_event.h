#pragma once
/// @file next_event.h
/// Next-event estimation (NEE), the one implementation every integrator calls: at a non-delta
/// shading point, a point of each chosen light or emitter, a shadow ray towards it, the BSDF and
/// the power-heuristic weight against BSDF sampling.
///
/// Which emitters a vertex takes comes from a LightSampler (render/lights/light_sampler.h), which only
/// chooses: one emitter per requested group by a light tree (LightStrategy::Tree), or every light
/// (LightStrategy::All, as nextEventEveryLight()). This file samples the point on the chosen
/// emitter (LightSet::sample for a light, a uniform point of an area-light triangle or of a lit
/// first-shot patch side, render/firstshot/patch_emitters.h) and weighs it; nextEventPdf() is the
/// density the same choice gives a point met by a BSDF-sampled path, for its MIS weight.
///
/// Every light (nextEventEveryLight, and LightStrategy::All): light l takes the sampler's
/// dimensions d0 + 2l and d0 + 2l + 1, drawn for the lights taken only, so later dimensions do not
/// shift. One emitter per group (Tree): each requested group takes one next2D pair, skipped without
/// drawing when the group is empty: x chooses the emitter and, rescaled within the chosen emitter's
/// share of [0,1) (LightSampler::sample's rest), is the point's first number, y its second. So the
/// pair's stratification covers the whole light (both triangles of a quad, say), not the choice
/// and the point separately.
///
/// The scene's infinite light (a sky or an environment map) is a kept light: one more choice of the kept
/// group beside the tree (light_sampler.h), its direction drawn from the map's density; with every light, one
/// sample after the lights' dimensions (d0 + 2n, d0 + 2n + 1), so scenes without it draw as before.
#include <cstdint>
#include <vector>

#include "common/materials/bsdf.h"
#include "common/sampling/rng.h"
#include "common/util/math.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

class FirstShotLighting;  // render/firstshot/lighting.h
class LightSampler;       // render/lights/light_sampler.h

/// The receiver normal with which a shading point weighs the emitters (the light tree's hemisphere): @p sideNormal,
/// the geometric normal on the viewer's side, or 0 (every direction) for a non-delta BSDF that transmits
/// (rough glass: a light behind the surface shines through it). NEE and nextEventPdf must be given the same one.
inline Vec3 receiverNormal(const BSDF& bsdf, const Vec3& sideNormal) {
  return bsdf.hasTransmission() && !bsdf.hasDelta() ? Vec3(0.0f) : sideNormal;
}

/// Power heuristic (β = 2) weight of a technique with density @p a against one with density @p b.
inline float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

/// A shadow ray from the hit towards a light @p distance (m) away in direction @p wi: from the hit's
/// offset origin straight at that point (not parallel to @p wi), stopping eps + 1e-4·distance short
/// of it, since the light may be emitter geometry itself.
Ray shadowRay(const Hit& hit, const Vec3& wi, float distance);

/// What one vertex takes by next-event estimation, and how it weights it.
struct NeeRequest {
  bool kept = false;      ///< the lights the table does not replace (every light without a table)
  bool replaced = false;  ///< the table's small lights (a vertex that does not use the table)
  bool patches = false;   ///< the first-shot patches (a LightSampler built with patch emitters)
  /// The luminaires' lights (a LightSampler built with luminaires, render/scene/luminaire_boxes.h; their exit
  /// patches are kept emitters): the light that leaves a box straight from them is not in its exit distribution.
  bool inner = false;
  /// The luminaire whose lights this vertex does not take, or −1: the vertex is inside its box on a path that
  /// entered it from a non-delta vertex, whose exit distribution holds all that light.
  int exceptLuminaire = -1;
  /// Weight area emitters against BSDF sampling (power heuristic); false: weight 1, for callers
  /// whose BSDF-sampled rays never count these emitters.
  bool mis = true;
  /// Replaced lights at a hit on a patch: no shadow ray where the table finds the light visible
  /// from the whole patch or from none of it (FirstShotLighting::visibility).
  bool tableVisibility = false;
  /// Integrate only f − ρd/π, the BSDF without its Lambertian part (the part an irradiance cache
  /// leaves out).
  bool nonDiffuseOnly = false;
  /// nextEventEveryLight: take the infinite light (sky, environment map) even when its @c include leaves some lights
  /// out (the irradiance cache, whose direct light is every light but the large area ones it gathers).
  bool infinite = false;
};

/// nextEvent()'s sum split by what each term sampled, W/(m² sr), for a report of where an image's variance comes from
/// (render/integrators/common/path_recorder.h). The four parts add up to the sum but for float rounding.
struct NeeParts {
  Color kept{0.0f};         ///< the kept lights (the infinite light apart)
  Color replaced{0.0f};     ///< the table's small lights
  Color patches{0.0f};      ///< the lit first-shot patches
  Color environment{0.0f};  ///< the infinite light (sky, environment map)
};

/// NEE at a non-delta vertex through @p lights: Σ f·|cos θ_i|·L/pdf over the chosen emitters that
/// are unoccluded, area emitters weighted against BSDF sampling. @p rays counts the shadow rays.
/// @p parts, if given, also receives the terms by what they sampled (added to what it holds).
Color nextEvent(const LightSampler& lights, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                const NeeRequest& request, Sampler& sampler, uint64_t& rays, NeeParts* parts = nullptr);

/// NEE to every light of @p scene that @p request takes (kept, replaced) and @p include allows
/// (nullptr: all; else (*include)[l] != 0, indexed like LightSet::lights()): one sample per light.
/// @p lighting answers NeeRequest::tableVisibility (unused otherwise). @p parts: as nextEvent()'s.
Color nextEventEveryLight(const RenderScene& scene, const FirstShotLighting& lighting,
                          const std::vector<uint8_t>* include, const Hit& hit, const Frame& frame, const Vec3& woLocal,
                          const BSDF& bsdf, const NeeRequest& request, Sampler& sampler, uint64_t& rays,
                          NeeParts* parts = nullptr);

/// NEE to every luminaire of @p lights (a sampler built with luminaires; 0 otherwise): one point of each one's exit
/// patches (chosen as nextEvent() chooses them, the luminaire's choice probability 1) and its specular light, as the
/// kept emitters they are; @p request's weighting. The luminaires' lights are not in it (nextEventEveryLight).
/// Luminaire i takes the sampler's dimensions d0 + 2i and d0 + 2i + 1.
Color nextEventEveryLuminaire(const LightSampler& lights, const Hit& hit, const Frame& frame, const Vec3& woLocal,
                              const BSDF& bsdf, const NeeRequest& request, Sampler& sampler, uint64_t& rays);

/// Solid-angle density with which nextEvent() at @p x, receiving side normal @p n, under
/// @p request, samples the point of @p y: a hit on an area light or on a patch. 0 where that
/// emitter is not requested (or not an emitter).
float nextEventPdf(const LightSampler& lights, const Vec3& x, const Vec3& n, const NeeRequest& request, const Hit& y);

/// Solid-angle density with which nextEvent() at @p x, receiving side normal @p n, under @p request, samples the point
/// @p y of exit patch number @p exit (render/scene/luminaire_boxes.h), met by a segment that crosses its face; 0 where
/// the sampler has no luminaires or @p request does not take the kept emitters.
float nextEventExitPdf(const LightSampler& lights, const Vec3& x, const Vec3& n, const NeeRequest& request,
                       uint32_t exit, const Vec3& y);

/// Solid-angle density with which nextEvent() under @p request samples direction @p dir (unit) of the scene's
/// infinite light (LightSet::environment), for the MIS weight of a path that escapes along it: 0 without one or
/// when @p request does not take the kept lights.
float nextEventEnvironmentPdf(const LightSampler& lights, const NeeRequest& request, const Vec3& dir);

/// One point of a lit first-shot patch chosen for a receiver (samplePatchEmitter).
struct PatchSample {
  Vec3 wi{0.0f};        ///< unit direction from the receiver to the point
  float distance = 0;   ///< m
  Color Le{0.0f};       ///< first-shot radiance the point sends towards the receiver, W/(m² sr)
  float pdf = 0;        ///< solid-angle density of wi (emitter choice included), sr⁻¹
};

/// Chooses a point of a lit patch for the receiver at @p x with receiving side normal @p n from
/// @p u ∈ [0,1)³ (u.x the patch, u.yz the point), as nextEvent() does for NeeRequest::patches,
/// without a shadow ray. @return false if none was chosen or it sends nothing towards @p x;
/// otherwise @p s.pdf equals nextEventPdf(lights, x, n, {patches}, hit at the point).
bool samplePatchEmitter(const LightSampler& lights, const Vec3& x, const Vec3& n, const Vec3& u, PatchSample& s);

}  // namespace firstshot
