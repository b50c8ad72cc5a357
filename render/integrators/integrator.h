#pragma once
/// @file integrator.h
/// The integrator interface (Nori / pbrt style): preprocess() once per scene, then a const,
/// thread-safe radiance estimate per camera sample.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/sampling/rng.h"
#include "common/util/comm.h"
#include "common/util/math.h"
#include "render/lights/light_sampler.h"
#include "render/scene/camera.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

struct PathVertex;  // render/integrators/common/path_walk.h

/// Extras an integrator reports for one camera sample.
struct SampleInfo {
  Color albedo{0.0f};   ///< AOV: reflectance at the first hit (0 when the ray escapes)
  Vec3 normal{0.0f};    ///< AOV: world-space geometric normal at the first hit, facing the camera
  uint64_t rays = 0;    ///< rays traced for this sample (closest-hit and shadow)
};

/// How the camera-visible vertex (the first non-specular vertex) treats small lights when a
/// first-shot table is present.
enum class PrimaryMode : uint8_t {
  Exact,  ///< shadow rays to the small lights: sharp shadows; first-shot from the next vertex on
  Patch,  ///< first-shot there too: shadows blurred at patch scale, no shadow rays to small lights
};

/// Where a path samples the lit first-shot patches as light sources (render/lights/light_sampler.h).
enum class PatchNee : uint8_t {
  Off,    ///< nowhere: a lit patch counts only when a BSDF sample meets it
  First,  ///< at the path's first non-delta vertex (its camera-visible surface), MIS against BSDF sampling
  Every,  ///< at every non-delta vertex
};

/// Settings shared by the integrators.
struct IntegratorOptions {
  int maxDepth = 16;  ///< longest path in bounces: 0 = emitters seen directly only, 1 = direct lighting
  int rrDepth = 3;    ///< Russian roulette from this many bounces on
  PrimaryMode primary = PrimaryMode::Exact;
  /// How NEE chooses lights: one sample of every light, or one light chosen by a light tree.
  LightStrategy lightSampler = LightStrategy::Tree;
  /// With a first-shot table: where to sample the lit patches as area emitters.
  PatchNee patchNee = PatchNee::Off;
  /// Weight the light trees by the visibility of their emitters, estimated per grid cell.
  bool lightVisibility = true;
  /// With a table that has luminaires (common/table/luminaire.h): sample their exit patches and see through their boxes
  /// (render/scene/luminaire_boxes.h). The path tracer's walk takes them; false: their lights are ordinary lights.
  bool luminaires = true;
  /// Light tracing and BDPT with luminaires: split every luminaire's light at its box (tests), not only those whose
  /// split pays on the camera's picture (render/integrators/common/luminaire_split.h).
  bool splitEveryLuminaire = false;
  /// With a first-shot table, where the small lights are sampled with shadow rays (PrimaryMode::Exact):
  /// no shadow ray to a point or spot light the table finds visible from the whole patch or from
  /// none of it (FirstShotLighting::visibility).
  bool tableVisibility = true;
  /// Shooting integrators (light tracing, bidirectional path tracing) with a first-shot table: the
  /// small lights' particles start from the patches the table lights and their direct light at the
  /// first non-delta camera vertex is taken exactly (render/integrators/light/integrator.h);
  /// false: the table is ignored (the small lights are shot like the others).
  bool shootFromPatches = true;
  /// Light tracing: light paths per pixel in each pass (the pass's one camera sample per pixel goes
  /// with them). 0 = automatic: 8, or 1 when the scene has mirrors or glass (the camera samples then
  /// carry what is seen through them).
  int lightPathsPerPixel = 0;
  /// Light tracing: at most this many light paths per pixel and pass where they are automatic (0: no cap). The
  /// pilot of `--integrator auto` caps them so that its two passes fit its share (PilotPlan::lightPaths).
  int lightPathsCap = 0;
  /// Light tracing and BDPT: choose the particles' emitters by what the camera sees of each one's light (a short
  /// measuring run, render/integrators/common/emitter_importance.h), not by their power alone.
  bool cameraEmitterChoice = true;
  /// The ranks of an MPI run sharing the work (common/util/comm.h; null: this process alone). Integrators
  /// with a global state (the irradiance cache's two-pass fill, the bundle's transfer) split its
  /// computation over the ranks and exchange the results, so that every rank holds the state one
  /// process would make, bit for bit.
  Comm* comm = nullptr;
};

/// A point an integrator has stored (an irradiance-cache record), for the preview's overlay.
struct IntegratorRecord {
  Vec3 position{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};  ///< unit surface normal
  float radius = 0.0f;            ///< radius of validity, m
};

/// A contribution a splatting integrator adds to one pixel in one pass.
struct Splat {
  uint32_t pixel = 0;  ///< y·width + x
  Color L{0.0f};       ///< added to the pixel's estimate of the pass, W/(m² sr)
};

/// The rays of task @p task of a cache fill (RayTask): it calls @p li for each ray, with the
/// sampler that ray's later Li() call will be given, and li returns the radiance.
using RayTask = std::function<void(size_t task, const std::function<Color(const Ray&, Sampler&)>& li)>;

/// How an integrator renders: which render loop drives it (render/loop/renderer.h's render()).
enum class IntegratorKind : uint8_t {
  Sampling,   ///< a radiance estimate per camera sample, Li() (path, irradiance-cache)
  Splatting,  ///< a SplattingIntegrator: each pass also traces particles splatted into the pixels (light, bdpt)
  PerPass,    ///< a PassIntegrator: a global state per sample index, advanced by beginPass() (bundle)
};

/// The interface every integrator has: preprocess(), then Li() per camera sample. kind() says
/// which render loop it takes; the splatting and per-pass ones derive from SplattingIntegrator
/// and PassIntegrator, which add what their loop calls. No integrator holds another: what two
/// share is a component of render/integrators/common/ (docs/architecture.md).
class Integrator {
 public:
  virtual ~Integrator() = default;
  /// Sampling, unless the integrator derives from SplattingIntegrator or PassIntegrator.
  virtual IntegratorKind kind() const { return IntegratorKind::Sampling; }
  /// Called once before rendering; @p scene must outlive the integrator's use.
  virtual void preprocess(const RenderScene& scene) = 0;
  /// Instead of preprocess() when the rays do not start at the scene's camera (sensors): an
  /// integrator that caches what the rays meet (the irradiance cache in two-pass mode) fills its
  /// cache from the rays of tasks 0 .. @p tasks − 1 instead of the camera's pixels, so that Li()
  /// then finds its records for those rays (and, nearby, for others). @p rayAngle (rad) is the
  /// angular footprint of one ray, the camera's pixel angle for such rays (the irradiance cache's
  /// footprint clamp). The integrator's lightSampler() is built before the first task runs, so a
  /// task may use it. Default: preprocess().
  virtual void preprocessRays(const RenderScene& scene, size_t /*tasks*/, const RayTask& /*task*/, float /*rayAngle*/) {
    preprocess(scene);
  }
  /// As preprocess(), for rendering pictures of the same view as @p camera, at its size or finer, instead of the
  /// scene's own picture (--integrator auto's pilot, render/loop/integrator_pilot.h). Only an integrator whose
  /// preprocessing depends on the camera (the irradiance cache's fill) overrides it. Default: preprocess().
  virtual void preprocessFor(const RenderScene& scene, const CameraDesc& /*camera*/) { preprocess(scene); }
  /// Lets the next preprocess() or preprocessFor() stop once it has traced more than @p rays rays (0: no limit), for a
  /// caller that drops an integrator whose preprocessing outgrows its budget (--integrator auto's pilot): stopped so,
  /// the integrator is not fit to render, and preprocessRayCount() exceeds @p rays. The irradiance cache's fill stops
  /// between its batches (the same place for any thread count); the default ignores it.
  virtual void limitPreprocessRays(uint64_t /*rays*/) {}
  /// Lets the next preprocess() stop once it has taken @p seconds (0: no limit), for a render given a time (--time):
  /// stopped so, the integrator stays fit to render with what it made. The irradiance cache's fill stops between its
  /// batches, its records made for the pixels of its coarse-to-fine order so far (a sample they do not cover takes a
  /// path); with several MPI ranks it is not stopped (the ranks would stop at different batches). Default: ignored.
  virtual void limitPreprocessSeconds(double /*seconds*/) {}
  /// Rays traced by preprocess() or preprocessFor() (the irradiance cache's fill), not counted in the render's
  /// RenderStats::rays; 0 by default.
  virtual uint64_t preprocessRayCount() const { return 0; }
  /// Seconds those rays took on this machine (the irradiance cache's fill, its setup left out); 0 by default.
  virtual double preprocessSeconds() const { return 0.0; }
  /// True if preprocess() draws random numbers of the seed the integrator was made for (the irradiance cache's
  /// fill), so that renders of another seed need another integrator; false by default: one preprocessed
  /// integrator renders any seed (RenderOptions::seed).
  virtual bool seededPreprocess() const { return false; }
  /// Replaces the random values a seeded preprocessing made (the irradiance cache's records' irradiance) by one more
  /// draw from their own error, as far as the preprocessing measured it (preprocessFor): rendered with the same
  /// samples, the picture differs from the unperturbed one by what those values' own noise does to it, which more of
  /// them at the same precision would not reduce (--integrator auto's pilot). The default does nothing.
  virtual void perturbPreprocessing(uint64_t /*seed*/) {}
  /// Where a seeded preprocessing's render takes a path for a sample its results do not cover (a lookup that finds
  /// no record of the irradiance cache's), that path draws its numbers from a stream keyed by the sample and
  /// @p salt, not from the sample's own, so that the rest of the sample stays as it is and another salt redraws the
  /// path alone: the pilot tells so what those paths' noise adds to the difference between two preprocessings'
  /// pictures over the same samples. 0 (the default state): from the sample's own. The default does nothing.
  virtual void keyMissPaths(uint64_t /*salt*/) {}
  /// The light sampler with which the integrator's paths choose lights for next-event estimation,
  /// over every light (kept and replaced); its lighting() is the first-shot lighting the integrator
  /// built. Both are built once by preprocess() (or preprocessRays()) and shared: the sensors' NEE
  /// uses them (render/sensors/sensors.h). Null (the default) for an integrator without such a
  /// sampler; one whose supportsSensors() is true has one.
  virtual const LightSampler* lightSampler() const { return nullptr; }
  /// Radiance arriving at the camera along @p ray (d unit length), estimated with @p sampler.
  /// Thread-safe. @p info, if given, receives the AOVs and the ray count.
  virtual Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const = 0;
  /// Radiance arriving at a sensor along @p ray (render/sensors/sensors.h), for an integrator whose lightSampler()
  /// samples the luminaires: the ray leaves @p from, a non-delta vertex whose next-event estimation took from.nee, so
  /// that a luminaire's box the ray enters counts its exit light, weighted against that NEE, and not its lights'
  /// light inside the box (render/scene/luminaire_boxes.h), as on any path past its first bounce. Default: Li().
  virtual Color LiFromSensor(const Ray& ray, const PathVertex& /*from*/, Sampler& sampler, SampleInfo* info) const {
    return Li(ray, sampler, info);
  }
  /// The camera rays of a 4 × 4 pixel block at one sample index (k = 4·row + column, k < @p count):
  /// L[k] = Li(rays[k], samplers[k], &infos[k]) for every k with wanted[k]. An integrator may trace
  /// the rays with traced[k] (a superset of the wanted ones: all of the block's pixels in the image,
  /// so that what a ray meets never depends on which pixels are wanted) as one coherent packet;
  /// rays[k] must then be finite for every k < @p count. Default: Li() per wanted ray.
  virtual void LiBlock(const Ray* rays, const bool* /*traced*/, const bool* wanted, int count, Sampler* samplers,
                       SampleInfo* infos, Color* L) const {
    for (int k = 0; k < count; ++k)
      if (wanted[k]) L[k] = Li(rays[k], samplers[k], &infos[k]);
  }
  virtual std::string name() const = 0;
  /// True if Li() alone estimates the radiance along any ray (no splats, no per-pass state): the
  /// sensor mode needs it, with lightSampler() (render/sensors/sensors.h). False by default.
  virtual bool supportsSensors() const { return false; }
  /// Why a checkpointed render with this integrator would not resume to the same image, bit for
  /// bit (render/loop/checkpoint.h); empty (the default): it would.
  virtual std::string notResumable() const { return {}; }
  /// True for integrators that store records (irradiance caching); false by default.
  virtual bool hasRecords() const { return false; }
  /// The records stored so far, for display. The preview calls it between render passes only.
  virtual std::vector<IntegratorRecord> records() const { return {}; }
};

/// Splatting integrators (light tracing, BDPT): each pass, besides one Li() per pixel, traces
/// particlesPerPass() particles whose splats are summed into the pass's pixel estimates
/// (render/loop/splat_renderer.h).
class SplattingIntegrator : public Integrator {
 public:
  IntegratorKind kind() const final { return IntegratorKind::Splatting; }
  /// Particles per pass for @p camera.
  virtual uint64_t particlesPerPass(const Camera& camera) const = 0;
  /// Traces particles [begin, end) of pass @p pass, each keyed by (seed, particle, pass), appending
  /// their splats to @p out in particle order. Thread-safe. @p mode: how the particles' samplers
  /// draw (RenderOptions::sampler); a particle's numbers stay a function of (seed, particle, pass).
  /// @p rays counts the rays traced. The renderer drops (and counts in RenderStats::nonFinite)
  /// splats that are NaN or Inf. @p jitterSeed: that of a particle's position in its pixel where it starts at the
  /// camera (BDPT; RenderOptions::jitterSeed, cameraJitter), @p seed where they are the same.
  virtual void splatParticles(const Camera& camera, uint64_t seed, uint64_t jitterSeed, SamplerMode mode, uint64_t pass,
                              uint64_t begin, uint64_t end, std::vector<Splat>& out, uint64_t& rays) const = 0;
};

/// Integrators with a global state per sample index (ray-bundle stochastic iteration): render()
/// takes one sample per pixel per pass and calls beginPass() before each pass.
class PassIntegrator : public Integrator {
 public:
  IntegratorKind kind() const final { return IntegratorKind::PerPass; }
  /// Called by render() before the camera samples of sample index @p sampleIndex, inside the
  /// render's thread arena and never while Li() runs: the integrator updates its (mutable)
  /// per-pass state here.
  virtual void beginPass(int sampleIndex, uint64_t seed) const = 0;
};

/// The names makeIntegrator accepts, in the order the preview offers them (keys 1, 2, ...).
std::vector<std::string> integratorNames();

/// An integrator by name ("path"), with its default settings (its line of integratorTable(),
/// render/integrators/integrator_cli.h). @throws InputError for an unknown name.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const IntegratorOptions& options);

}  // namespace firstshot
