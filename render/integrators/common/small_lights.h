#pragma once
/// @file small_lights.h
/// The shooting integrators with a first-shot table (table mode: bidirectional path tracing,
/// docs/bdpt.md, and light tracing): the part of a camera subpath that the small (replaced) lights
/// still contribute as themselves.
///
/// In table mode the small lights leave the emission sampler; their first reflection comes from
/// the lit patches, which emit it at camera vertices after x_m, the first non-delta vertex of the
/// camera subpath (render/firstshot/patch_emitters.h). What is left for the lights themselves is, as in the
/// path tracer's exact primary mode (PrimaryMode::Exact):
///   - a small area light met by the camera subpath up to x_m (through mirrors and glass): weight 1;
///   - the direct light at x_m: next-event estimation to the small lights (nextEvent), and a
///     small area light met by the subpath's BSDF sample from x_m, weighted against it by the
///     power heuristic;
///   - a small area light met later right after a delta bounce (no table or NEE holds it): weight 1.
/// BDPT passes its whole camera subpath. Light tracing (render/integrators/light/integrator.h)
/// passes x_m (the camera's first hit) and the hit of x_m's BSDF sample only: light reflected by
/// mirrors and glass before x_m comes from its delta-first particles there.
#include <span>

#include "common/rng.h"
#include "render/integrators/integrator.h"
#include "render/integrators/common/subpath_vertex.h"
#include "render/lights/light_sampler.h"
#include "render/lights/next_event.h"

namespace fs {

class SmallLightsExact {
 public:
  /// @p lighting must be built for @p scene; both must outlive the object.
  void build(const RenderScene& scene, const FirstShotLighting& lighting, const IntegratorOptions& options);
  /// The small lights' contribution to the camera subpath @p camera (vertex 0 the pinhole) whose
  /// first non-delta vertex is @p m (camera.size() if none), W/(m² sr). Draws the NEE sample's
  /// dimensions from @p sampler; @p rays counts the shadow rays.
  Color estimate(std::span<const SubpathVertex> camera, size_t m, Sampler& sampler, uint64_t& rays) const;

 private:
  const RenderScene* scene_ = nullptr;
  LightSampler lights_;
  /// The replaced lights, with MIS; no shadow ray where the table decides (IntegratorOptions::tableVisibility).
  NeeRequest request_{false, true, false, true};
};

}  // namespace fs
