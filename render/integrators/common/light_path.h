#pragma once
/// @file light_path.h
/// Light subpaths: a particle leaves a light (EmissionSampler) and bounces by sampling the
/// adjoint BSDF (TransportMode::Importance) with Russian roulette. The vertex list is what light
/// tracing connects to the camera, and what a bidirectional integrator connects to eye vertices.
#include <cstdint>
#include <vector>

#include "common/sampling/rng.h"
#include "render/lights/light_emission.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// One vertex of a light subpath. Vertex 0 lies on the light; vertex k ≥ 1 is the particle's k-th
/// surface hit, reached after k − 1 reflections.
struct LightVertex {
  Hit hit;                  ///< vertex 0: p, ng (area light: front normal) and eps only
  Vec3 wi{0.0f};            ///< unit direction to the previous vertex (the light side); 0 at vertex 0
  /// Vertex 0: the emitted radiance over the position density, Le/(p_light·p_pos) (area lights; 0
  /// for delta lights). Vertex k ≥ 1: the particle's power arriving at the vertex, W (before the
  /// BSDF there): Σ over particles / N estimates the flux the vertex's surface receives.
  Color beta{0.0f};
  /// Area density of the vertex given the previous one, 1/m² (vertex 0: p_light·p_pos, with p_pos = 1
  /// for a delta position); the density of the previous vertex's direction is pdfDir·|cosθ|/d².
  float pdfFwd = 0;
  /// Solid-angle density with which this vertex chose the next direction (vertex 0: the emission
  /// direction's), 1/sr; the discrete lobe probability after a delta lobe.
  float pdfDir = 0;
  uint32_t material = kNoId;  ///< kNoId at vertex 0
  uint32_t light = kNoId;     ///< vertex 0: the light's index in LightSet::lights(); kNoId after it
  bool delta = false;         ///< a delta BSDF, or a delta light (position or direction) at vertex 0
};

/// Settings of the random walk.
struct LightPathOptions {
  int maxDepth = 16;  ///< vertices 1..maxDepth at most: a vertex k connected to the camera makes a path of k bounces
  int rrDepth = 3;    ///< Russian roulette once the particle has bounced this many times
  bool sqrtSurvival = true;  ///< the roulette's survival: SubpathWalkSettings::sqrtSurvival
  /// Stop at a first hit that is not a delta surface (light tracing's delta-first particles of the
  /// small area lights in table mode: the table holds their other first bounces). A delta first hit
  /// stops too where the light is delta (a point, spot or directional light: the path tracer cannot
  /// close such paths either).
  bool deltaFirstHitOnly = false;
  /// With deltaFirstHitOnly: also go on from a first hit too sharp for the table
  /// (BSDF::tooSharpForTable: the lit patches do not emit its reflection), from any light.
  bool polishedFirstHit = false;
  /// Light tracing with the luminaires' exit particles (EmissionSampler::addExits): a particle of a luminaire's light
  /// ends where it leaves that luminaire's box for the first time (its first hit outside the box is not recorded:
  /// the exit particles carry its light from the box on). Null: no luminaires (every other caller).
  const LuminaireBoxes* luminaires = nullptr;
};

/// Traces one light subpath into @p path (cleared first). A particle leaving an exit patch (addExits) starts with no
/// bounce made: its vertex 0 lies on the patch, in empty space. A particle leaving a lit patch (table
/// mode) has bounced once already: it makes at most maxDepth − 1 hits and meets roulette one
/// bounce earlier. Consumes the sampler's dimensions in a
/// fixed order: 5 for the emission, then per bounce 2 for the BSDF and, from rrDepth on, 1 for roulette. @p rays counts the
/// closest-hit rays. @p stratum of @p strata: the emitter's stratum (EmissionSampler::sample).
/// @return false if the light emitted nothing (the path is then empty).
bool traceLightPath(const RenderScene& scene, const EmissionSampler& emission, const LightPathOptions& options,
                    Sampler& sampler, std::vector<LightVertex>& path, uint64_t& rays, uint64_t stratum = 0,
                    uint64_t strata = 1);

}  // namespace firstshot
