#pragma once
/// @file integrator.h
/// Bidirectional path tracing (Veach 1997; Lafortune & Willems 1993), docs/bdpt.md.
///
/// A sample of pixel j in pass k is a camera subpath through pixel j and a light subpath (the
/// shared traceLightPath, render/integrators/common/light_path.h), both keyed by
/// Sampler::make(mode, seed, j, k, kStream). Every strategy (s, t) of s light and t camera vertices is evaluated — s = 0 (the
/// camera path meets an area light), s = 1 (a new light sample), s ≥ 2 with t ≥ 2 (a shadow ray
/// between the subpaths), and t = 1 (a light vertex joined to the pinhole, splatted where it
/// projects as light tracing does: connectToCamera, common/camera_splat.h) — and weighted by the
/// power heuristic over all strategies of the same path (misWeight). Paths of more than
/// IntegratorOptions::maxDepth bounces (s + t − 2) are left out (docs/irradiance-cache.md, "What
/// --max-depth counts").
///
/// The whole sample is a particle of the deterministic splat loop (render/loop/splat_renderer.h): the
/// t ≥ 2 strategies go to pixel j as one splat (one sample per pixel per pass), the t = 1 ones to
/// the pixels they reach, over N = width·height. Images are bit-identical for any thread count.
/// Li() gives only the AOVs.
///
/// With a first-shot table and IntegratorOptions::shootFromPatches (table mode): the small lights'
/// light subpaths start from the patches the table lights — the table is their first bounce. The
/// emitters are the kept lights and the lit patch sides (common/shooting_emitters.h): light
/// subpaths leave them, s = 1 samples them, and a camera vertex after x_m (the first non-delta one)
/// on a lit patch meets its first-shot radiance (s = 0). The small lights themselves add their
/// direct light at x_m and what no table can hold (SmallLightsExact, common/lights/small_light_rule.h). A small
/// area light's light whose first bounce is a mirror or glass (no table holds it: the bulb inside a
/// glass envelope, a caustic) has its own light subpaths as well, as in light tracing: a second light
/// subpath per sample leaves the small area lights and is kept only if its first hit is delta; its
/// strategies and the camera subpath meeting a small light right after a delta vertex are weighted
/// against each other (docs/bdpt.md, "Delta-first light subpaths").
/// Without the option the table is ignored: the small lights are shot and sampled like all others
/// (unbiased, as light tracing).
///
/// With luminaires (IntegratorOptions::luminaires and a table that has them) the emitters are light tracing's
/// (emittersWithExits, common/luminaire_split.h): a luminaire whose split pays on the camera's picture is split at
/// its box, its exit patches' light subpaths and samples (s = 1) carrying the light that leaves the box after a bounce
/// inside it, and its lights' strategies only the other paths (exitPatchesPath, luminaire_paths.h). No camera
/// subpath meets an exit patch (s = 0): rays see through the boxes, and a camera looking into a shade sees its inside
/// lit by its lights (docs/bdpt.md, "Luminaires").
#include <vector>

#include "render/integrators/bdpt/densities.h"
#include "render/integrators/common/light_path.h"
#include "render/integrators/common/shooting_integrator.h"

namespace firstshot {

/// A shooting integrator (common/shooting_integrator.h): its preprocess() is all BDPT needs.
class BdptIntegrator : public ShootingIntegrator {
 public:
  using ShootingIntegrator::ShootingIntegrator;
  /// The shooting integrators' preprocess(), then (table mode) the delta-first emitters.
  void preprocess(const RenderScene& scene) override;
  /// The AOVs of the camera ray's first hit; radiance 0 (the splats carry it).
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  std::string name() const override { return "bdpt"; }

  uint64_t particlesPerPass(const Camera& camera) const override {
    return uint64_t(camera.width()) * uint64_t(camera.height());
  }
  /// Particle i is the sample of pixel i (row-major).
  void splatParticles(const Camera& camera, uint64_t seed, uint64_t jitterSeed, SamplerMode mode, uint64_t pass,
                      uint64_t begin, uint64_t end, std::vector<Splat>& out, uint64_t& rays) const override;

  /// The stream index of the samples' samplers: Sampler::make(mode, seed, pixel, pass, kStream) (in
  /// Sobol' mode a pixel's passes are its sequence's indices, as the tile renderer's samples).
  static constexpr uint64_t kStream = 0x4250;  // "BP"
  /// The stream of table mode's delta-first light subpaths (their own sampler, so that the other
  /// strategies draw the same numbers with and without them).
  static constexpr uint64_t kDeltaFirstStream = 0x4244;  // "BD"

 private:
  /// Subpaths of one sample, reused across the particles of a chunk.
  struct Workspace {
    std::vector<SubpathVertex> camera, light, deltaLight;
    std::vector<LightVertex> lightRaw, deltaRaw;
  };
  /// One sample of pixel @p pixel: appends its splats to @p out. @p deltaDensities: those of the
  /// delta-first light subpaths (deltaFirst_), drawn from @p deltaSampler.
  void sample(const BdptDensities& densities, const BdptDensities& deltaDensities, uint32_t pixel, const Vec2& jitter,
              Sampler& sampler, Sampler& deltaSampler, Workspace& ws, std::vector<Splat>& out, uint64_t& rays) const;
  /// Table mode: the delta-first light subpath's strategies with the camera subpath in @p ws (whose first
  /// non-delta vertex is @p m), and the camera subpath meeting a small area light right after a delta
  /// vertex: returns the t ≥ 2 part, appends the t = 1 splats to @p out.
  Color deltaFirstStrategies(const BdptDensities& deltaDensities, size_t m, Sampler& deltaSampler, Workspace& ws,
                             std::vector<Splat>& out, uint64_t& rays) const;

  /// Table mode, a scene with mirrors or glass and small area lights: shoot delta-first light subpaths.
  bool deltaParticles_ = false;
  /// Their emitters: the replaced area lights (LightSet indices, the others without power).
  EmissionSampler deltaFirst_;
  /// Whether a strategy whose light is LightSet light @p l makes the path of @p light[0 .. s) and @p camera[t−1 .. 0]
  /// for this integrator: not where the exit patches make it (exitPatchesPath).
  bool counts(uint32_t l, std::span<const SubpathVertex> light, int s, std::span<const SubpathVertex> camera,
              int t) const;
};

}  // namespace firstshot
