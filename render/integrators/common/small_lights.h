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
///   - a small area light met later right after a delta bounce (no table or NEE holds it): weight 1,
///     unless the caller weights these itself (BDPT, which also shoots the small area lights' light
///     subpaths whose first hit is a mirror or glass: @p skipDeltaChains);
///   - with @p polishedUpTo (BDPT): at every polished vertex after x_m (BSDF::tooSharpForTable, whose
///     lit patch emits nothing: render/firstshot/patch_emitters.h) up to that vertex number, the
///     direct light by NEE, and a small area light met by its BSDF sample, by the power heuristic —
///     the path tracer's rule at such a point.
/// BDPT passes its whole camera subpath. Light tracing (render/integrators/light/integrator.h)
/// passes x_m (the camera's first hit) and the hit of x_m's BSDF sample only: light reflected by
/// mirrors and glass before x_m, or by a polished surface, comes from its first-hit particles.
#include <span>

#include "common/sampling/rng.h"
#include "render/integrators/common/subpath_vertex.h"
#include "render/integrators/integrator.h"
#include "render/lights/light_sampler.h"
#include "render/lights/next_event.h"

namespace firstshot {

class SmallLightsExact {
 public:
  /// @p lighting must be built for @p scene; both must outlive the object.
  void build(const RenderScene& scene, const FirstShotLighting& lighting, const IntegratorOptions& options);
  /// The small lights' contribution to the camera subpath @p camera (vertex 0 the pinhole) whose
  /// first non-delta vertex is @p m (camera.size() if none), W/(m² sr); polished vertices after
  /// it up to vertex @p polishedUpTo (0: none) take the small lights' direct light as x_m does.
  /// Draws the NEE samples' dimensions from @p sampler (x_m's first); @p rays counts the shadow rays.
  /// @p skipDeltaChains: leave out a small area light met after x_m right after a delta vertex
  /// (afterDeltaChain()), which the caller then weights against its own strategies for that path.
  Color estimate(std::span<const SubpathVertex> camera, size_t m, Sampler& sampler, uint64_t& rays,
                 size_t polishedUpTo = 0, bool skipDeltaChains = false) const;
  /// Whether camera vertex @p i (after x_m = @p m) follows a delta vertex: a small area light met there
  /// lit the camera's path through a mirror or glass that no table holds.
  static bool afterDeltaChain(std::span<const SubpathVertex> camera, size_t i, size_t m) {
    return i > m + 1 && i < camera.size() && camera[i - 1].delta;
  }

 private:
  /// Whether camera vertex @p i takes the small lights' direct light by NEE: x_m, or a polished one up to
  /// @p polishedUpTo.
  bool gathers(std::span<const SubpathVertex> camera, size_t i, size_t m, size_t polishedUpTo) const;

  const RenderScene* scene_ = nullptr;
  LightSampler lights_;
  /// The replaced lights, with MIS; no shadow ray where the table decides (IntegratorOptions::tableVisibility).
  NeeRequest request_{false, true, false, true};
  bool polished_ = false;  ///< the scene may have polished points (mayBePolished)
};

}  // namespace firstshot
