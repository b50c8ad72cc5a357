#pragma once
/// @file path_walk.h
/// The unidirectional path-tracing walk, a component the gathering integrators share: the path
/// tracer (render/integrators/path/integrator.h) is a thin integrator over it, light tracing takes it for the
/// camera rays whose first hit is a mirror or glass, and the irradiance cache for the light past
/// its last cached level.
///
/// The walk does next-event estimation (render/lights/next_event.h: NEE to every light or one light
/// chosen by a light tree), multiple importance sampling (power heuristic) against BSDF sampling
/// for area emitters, and Russian roulette.
///
/// With a first-shot table (RenderScene::firstShot), the table's small lights leave light
/// sampling and emission: every non-delta vertex on patch j adds
///     Σ_i emission_i · r_ij · f_r(ω'_i, x, ω)
/// (FirstShotLighting), and, with patch NEE (IntegratorOptions::patchNee), every non-delta vertex
/// also samples the lit patches as area emitters of that radiance: a BSDF-sampled path that meets
/// a lit patch weights its first-shot term against that by MIS, so nothing is counted twice.
/// Large lights keep NEE + MIS; the scene's infinite light (a sky or an environment map) is one of them: NEE
/// samples it, a path that leaves the scene meets it (escaped()), a camera ray that does sees it as the background.
/// A small area light met by a path is counted only where the first-shot term could not have counted it: seen by the camera, after a delta bounce (mirror,
/// glass), or from a vertex that sampled it by NEE (PrimaryMode::Exact).
///
/// With luminaires in the table (render/scene/luminaire_boxes.h, IntegratorOptions::luminaires), their exit patches are
/// kept emitters, a segment from a non-delta vertex that enters a box adds the exit light where it crosses
/// (enterLuminaires, MIS against NEE), and the luminaire's lights are suppressed past that entry until the path
/// leaves the box; from the camera and delta bounces a box is entered as it is.
///
/// A report of where an image's variance comes from (bench/variance_report.h) sets the calling thread's
/// PathRecorder (path_recorder.h) around trace(): each amount added to L is then also told to it, by path length
/// and by what brought it (emission met, NEE per light group, the first-shot term, patch NEE). Without one the
/// walk computes exactly what it did before.
#include <cstdint>
#include <vector>

#include "render/lights/next_event.h"
#include "render/firstshot/lighting.h"
#include "render/integrators/integrator.h"
#include "render/lights/light_sampler.h"

namespace firstshot {

/// The vertex a path segment leaves from: what decides the weight of emission met at its end.
struct PathVertex {
  bool delta = true;        ///< the camera or a delta lobe: no light sampling could have found the next hit
  bool usedTable = false;   ///< the vertex took the replaced lights from the first-shot table
  float pdf = 0.0f;         ///< solid-angle density of the sampled direction
  Vec3 p{0.0f};             ///< position, m
  Vec3 n{0.0f};             ///< receiving normal passed to LightSampler (the viewer's side)
  NeeRequest nee;           ///< what the vertex sampled by NEE
  /// Lights (LightSet indices) the vertex counted in full by other means: they count 0 when met.
  const std::vector<uint8_t>* counted = nullptr;
  /// The vertex counted the infinite light (sky, environment map) in full by other means: it counts 0 when met.
  bool countedInfinite = false;
  /// The vertex counted the luminaires' exit light in full by other means (an irradiance cache's direct light): a box
  /// its segment enters adds none, and the luminaire's lights inside stay suppressed as after any counted entry.
  bool countedExits = false;
};

class PathWalk {
 public:
  /// Keeps @p scene and @p lighting (built for @p scene, shared with the owner: both must outlive
  /// the walk) and builds the walk's light sampler (light trees, patch emitters) as @p options say.
  void build(const RenderScene& scene, const FirstShotLighting& lighting, const IntegratorOptions& options);

  /// Radiance along @p ray times @p beta, for a path whose next hit is vertex number @p depth
  /// (0: seen from the camera) and leaves @p prev. @p specularChain: only delta bounces since the
  /// camera. @p rays counts the rays traced; @p info gets the AOVs of vertex 0. @p first, if given,
  /// is the closest hit of @p ray, already traced (and counted) by the caller. W/(m² sr).
  Color trace(Ray ray, Color beta, int depth, PathVertex prev, bool specularChain, Sampler& sampler, uint64_t& rays,
              SampleInfo* info = nullptr, const Hit* first = nullptr) const;

  /// The first-shot radiance reflected at a hit on patch hit.patch towards the local @p wo.
  Color firstShot(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const {
    return lighting_->eval(hit, frame, woLocal, bsdf);
  }
  const LightSampler& lightSampler() const { return lights_; }
  /// The lit patches' first-shot radiance (empty without a table), the owner's.
  const FirstShotLighting& lighting() const { return *lighting_; }

 private:
  /// Weight of emission met at @p hit (an area light or, for the first-shot term, a patch) by a
  /// segment from @p prev.
  float emissionWeight(const PathVertex& prev, const Hit& hit) const;
  /// Where a path is with respect to the luminaires (render/scene/luminaire_boxes.h).
  struct LuminaireState {
    int inside = -1;          ///< the luminaire whose box holds the current vertex, or −1
    bool suppressed = false;  ///< its exit light was counted where the path entered it: its lights emit nothing
    int depth = 0;            ///< the vertex the segment ends at (for a report)
  };
  /// The exit light of each luminaire box that the segment piece @p piece (from its tmin to @p tEnd) enters, seen
  /// from @p prev, the segment's first vertex: added to @p L times @p beta when @p prev is not delta, weighted
  /// against NEE's choice of that exit point.
  void enterLuminaires(const Ray& piece, float tEnd, const Color& beta, const PathVertex& prev, const LuminaireState& state,
                       Color& L) const;
  /// Radiance of the scene's infinite light (LightSet::environment; 0 without one) met by a segment from @p prev
  /// that leaves the scene along @p dir, weighted against NEE's choice of that direction (power heuristic).
  Color escaped(const PathVertex& prev, const Vec3& dir) const;

  IntegratorOptions options_;
  const RenderScene* scene_ = nullptr;
  const FirstShotLighting* lighting_ = nullptr;
  LightSampler lights_;
};

}  // namespace firstshot
