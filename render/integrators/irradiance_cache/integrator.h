#pragma once
/// @file integrator.h
/// Irradiance caching (Ward, Rubinstein & Clear 1988) on top of the first-shot renderer.
///
/// At every non-specular vertex the outgoing radiance is split as
///   L = [first-shot or NEE for the direct lights] + ρd/π · E_ℓ(x) + [non-diffuse part of f]
/// - Direct lights are the small ones (the first-shot table's, or by the scene's small-light rule
///   without a table) and every point, spot and directional light. With a table they come from
///   the first-shot term Σ_i emission_i r_ij f_r (NEE at the camera-visible vertex under
///   PrimaryMode::Exact); without one from NEE at the vertex. Rays of the cache and of BSDF
///   sampling that meet a small light count nothing, so nothing is counted twice.
/// - E_ℓ is the indirect irradiance at level ℓ, the vertex's index along the path as the path
///   tracer counts bounces (0 at camera-visible surfaces; mirrors, glass and glossy samples count
///   too; docs/irradiance-cache.md, "What --max-depth counts": vertex ℓ scatters only for
///   ℓ < maxDepth), interpolated from the records of level ℓ (eq. 5) or, if none is valid, computed by the
///   primary method: stratified cosine-weighted hemisphere sampling (eq. 2, M × 2M cells) whose
///   rays gather the radiance of the surfaces they hit at level ℓ+1 (first-shot or NEE direct
///   light plus their own cached indirect light) and the emission of large area lights (§5).
///   Level ℓ uses a·1.4^ℓ and half the samples of level ℓ−1 (§3.4). Past the last level the
///   irradiance is estimated without bias by one path per evaluation, π·L(ω) for a cosine-
///   distributed ω, L traced by the path walk (render/integrators/common/path_walk.h: its NEE,
///   first-shot patches as emitters, Russian roulette, over this integrator's first-shot
///   lighting), so the cache converges to what path tracing does; or, on request, it is
///   π·ambient (Ward's ambient term, biased).
/// - Direct light at a vertex is next-event estimation (nextEvent) through a LightSampler built over the
///   direct lights only: one light chosen by a light tree (IntegratorOptions::lightSampler =
///   Tree), or one sample of every direct light (All); weight 1 (mis off), since the cache's and
///   BSDF rays never count those lights.
/// - With a first-shot table and IrradianceCacheSettings::patchNee > 0, the primary method also
///   samples the lit first-shot patches as area emitters at the record point (patch NEE,
///   irradiance_cache_patch_nee.cpp) and combines those samples with the hemisphere rays' first-
///   shot terms by multiple importance sampling, so E stays unbiased; gradients and R come from
///   the hemisphere rays alone.
/// - With luminaires in the table (render/scene/luminaire_boxes.h, IntegratorOptions::luminaires): their light is
///   direct light. A camera vertex samples each one's exit patches and specular light (and their lights, where the path
///   tracer would) by NEE beside every other direct light; other vertices through the direct light sampler. A record's
///   or glossy ray that enters a box and meets something inside it counts nothing there of the luminaire's light: the
///   path continuation takes it on from that hit with the luminaire's lights suppressed (luminaires.cpp).
/// - Mirrors and glass are followed by ray tracing; the glossy part f − ρd/π of a stretched-Phong
///   BSDF by one BSDF-sampled ray per vertex, with NEE + MIS for the large lights.
///
/// Modes: one pass (records are made while rendering, shared by all threads; the image depends
/// on the thread schedule), or two passes: preprocess() fills the cache by tracing the render's
/// first camera sample(s) of every pixel in a fixed coarse-to-fine pixel order, in parallel
/// batches whose new records are merged in a fixed order, and sweeps again until every one of
/// those samples finds its records; the render then only reads the cache. A render lookup that
/// finds no record accepts the records of doubled domain (w > 1/(2a)), and failing that takes
/// one path from there (as past the last level: no bias), or with missRecords (and with --ambient)
/// makes a record private to that camera sample. The image is then bit-identical for any number of
/// threads, and the render's first samples are exactly as a one-pass render would make them.
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "render/firstshot/lighting.h"
#include "render/output/film.h"
#include "render/integrators/common/packet_integrator.h"
#include "render/integrators/irradiance_cache/cache.h"
#include "render/integrators/common/path_walk.h"

namespace firstshot {

/// Settings of the irradiance cache integrator (command-line names in brackets).
struct IrradianceCacheSettings {
  float accuracy = 0.15f;       ///< a of eq. 5 at level 0 [--accuracy]
  int samples = 512;            ///< hemisphere samples N of a level-0 record [--ic-samples]
  int bounces = 3;              ///< B: levels served by the cache, path vertices 0 .. B − 1 [--bounces]
  /// Past the last level: continue by path tracing (unbiased; default), or assume ambient.
  bool pathContinuation = true;
  Color ambient{0.0f};          ///< radiance assumed past the last level when !pathContinuation [--ambient]
  bool gradients = true;        ///< Ward & Heckbert rotational and translational gradients [--gradients]
  /// Footprint clamping (Tabellion & Lamorlette 2004): R_i is clamped so that the valid domain
  /// a_ℓ·R_i spans [min, max] pixel footprints at the record, a footprint being the width of a
  /// pixel's cone at the record's distance from the camera along the path (through mirrors and,
  /// for deeper levels, along the hemisphere rays too). 0 and ∞ disable it [--clamp-footprint MIN,MAX].
  float footprintMin = 1.5f;
  float footprintMax = 100.0f;
  bool neighbourClamp = true;   ///< R_i ≤ R_j + |P_i − P_j| (Křivánek et al. 2006) [--neighbour-clamp]
  bool twoPass = true;          ///< fill the cache in preprocess(), then render read-only [default; --one-pass: false]
  /// Two-pass render: a lookup that finds no record (not even in the doubled domains) makes a record private to that
  /// camera sample, as Ward's method would, instead of taking one path from there (the default) [--ic-miss record].
  bool missRecords = false;
  int fillSamples = 1;          ///< two-pass: camera samples per pixel of the fill (the render's first ones)
  std::string cacheFile;        ///< records read in preprocess() if the file exists [--cache-file]
  uint64_t seed = 1;            ///< the render's seed (the fill traces the render's own camera samples)
  SamplerMode sampler = SamplerMode::Independent;  ///< the render's sampler (RenderOptions::sampler), for the same reason
  int threads = 0;              ///< workers of the fill pass (0 = one per core)
  bool quiet = true;            ///< no progress of the fill on stderr (the tool's --quiet; rank 0 alone shows it)
  /// With a first-shot table: patch NEE samples per hemisphere ray of a record (rounded, at least
  /// one), MIS-combined with the rays' first-shot terms; 0 = off [--ic-patch-nee].
  float patchNee = 0.0f;
};

/// Counters of one run.
struct IrradianceCacheStats {
  size_t loaded = 0;            ///< records read from the cache file
  size_t records = 0;           ///< records in the cache now (all levels)
  std::vector<size_t> perLevel; ///< records per level
  uint64_t privateRecords = 0;  ///< two-pass render: records made for one camera sample only (missRecords, --ambient)
  uint64_t missPaths = 0;       ///< two-pass render: lookups that found no record and took one path
  double fillSeconds = 0;       ///< two-pass fill
  uint64_t fillRays = 0;        ///< rays the two-pass fill traced (closest-hit and shadow)
  int fillRounds = 0;           ///< fill sweeps (the last one finds every pixel covered)
  /// Records the fill's tasks made, and of them those an earlier task of the same batch had made already (dropped at
  /// the merge: work done twice, which the batches' sizes keep small).
  uint64_t fillMade = 0, fillDuplicates = 0;
  /// The fill stopped at limitPreprocessSeconds() after this many pixels of its last sweep (fillRounds; 0: it did not).
  size_t fillCutAt = 0;
  size_t fillPixels = 0;        ///< of a sweep's pixels (tasks)
  /// With several MPI ranks (IntegratorOptions::comm): bytes this rank sent in the fill's record
  /// exchanges, and the seconds it spent in them (waiting for the other ranks included).
  uint64_t exchangeBytes = 0;
  double exchangeSeconds = 0;
};

class IrradianceCacheIntegrator : public PacketIntegrator {
 public:
  explicit IrradianceCacheIntegrator(const IntegratorOptions& options, const IrradianceCacheSettings& settings = {});
  ~IrradianceCacheIntegrator() override;

  /// Replaces the settings; call before preprocess().
  void setSettings(const IrradianceCacheSettings& settings) { settings_ = settings; }
  const IrradianceCacheSettings& settings() const { return settings_; }

  /// Classifies the lights, creates the empty cache, reads the cache file if it exists (refusing
  /// it with InputError if it does not match), and in two-pass mode fills the cache for the
  /// scene's camera.
  void preprocess(const RenderScene& scene) override;
  /// As preprocess(), but a two-pass cache is filled from the rays of @p task (0 .. @p tasks − 1,
  /// e.g. the first samples of every sensor) instead of the camera's pixels, with the same
  /// batches and ordered merge: the records do not depend on the thread count. Those rays are
  /// Li()'s camera rays (level 0; the footprint clamp measures path length from their origins
  /// and takes @p rayAngle as the pixel angle). Afterwards a lookup that finds no record, not even
  /// in the doubled domains, estimates the irradiance by one path (as past the last level: no
  /// bias) instead of making a record private to that ray (with path continuation on); in the
  /// fill, so does a task's lookup once the task has traced 2^20 rays (a deterministic bound on
  /// the records one task makes, e.g. inside a closed object).
  void preprocessRays(const RenderScene& scene, size_t tasks, const RayTask& task, float rayAngle) override;
  /// preprocess() with the fill over @p camera's pixels and its pixel angle for the footprint clamp (--integrator
  /// auto's pilot renders a finer picture over them).
  void preprocessFor(const RenderScene& scene, const CameraDesc& camera) override;
  uint64_t preprocessRayCount() const override { return fillRays_; }
  double preprocessSeconds() const override { return fillSeconds_; }
  void limitPreprocessRays(uint64_t rays) override { fillRayLimit_ = rays; }
  void limitPreprocessSeconds(double seconds) override { fillSecondsLimit_ = seconds; }
  bool seededPreprocess() const override { return settings_.twoPass; }
  /// Every level-0 record's E_i replaced by max(0, E_i·(1 + z·s)), one normal z per record, s the RMS of
  /// spread/E over the records gathered twice (preprocessFor makes them); the octrees rebuilt. No-op without them.
  void perturbPreprocessing(uint64_t seed) override;
  void keyMissPaths(uint64_t salt) override { missSalt_ = salt; }
  std::string name() const override { return "irradiance-cache"; }
  bool supportsSensors() const override { return true; }
  /// The path continuation's light sampler, over every light (after preprocess() or preprocessRays()).
  const LightSampler* lightSampler() const override { return &continuation_.lightSampler(); }
  /// With luminaires (lightSampler() samples them): the path continuation from the sensor, no records (a record's
  /// gather would take the luminaires' light at the sensor's first hit, which the sensor's own NEE weighs by MIS).
  Color LiFromSensor(const Ray& ray, const PathVertex& from, Sampler& sampler, SampleInfo* info) const override;
  std::string notResumable() const override {
    return settings_.twoPass ? std::string()
                             : "the one-pass irradiance cache depends on the thread schedule and cannot resume exactly: "
                               "drop --one-pass";
  }
  bool hasRecords() const override { return true; }
  /// Level-0 records (radius = a·R_i, the valid domain).
  std::vector<IntegratorRecord> records() const override;

  /// Writes every record with the scene hash and settings (see cache_file.h).
  void saveCache(const std::string& path) const;
  /// Writes @p film with the pixels of the visible level-0 record positions in blue (Figure 5b).
  void writeRecordImage(const Film& film, const std::string& path, float exposure = 0.0f) const;
  IrradianceCacheStats stats() const;

  // Building blocks, public for tests.
  /// True if luminaire @p l's box holds a surface of @p scene that is not Lambertian (glass, a mirror, a glossy metal):
  /// its light then leaves by routes the records find only by chance (a filament through its glass, a bulb's
  /// reflection in a metal bowl), which its exit distribution and specular light sample directly. A box of Lambertian
  /// surfaces alone (a cove, a fabric shade) scatters its light diffusely, which the records gather as smoothly, and
  /// its exit patches, cut by the ceiling and walls the box takes in, are noisier to sample (docs/luminaires.md).
  static bool holdsNonLambertian(const RenderScene& scene, const Luminaire& l);
  /// a at level @p level: a·1.4^level.
  float accuracy(int level) const;
  /// Polar strata M at @p level; a record takes M × 2M samples (about N/2^level, at least 8).
  int strata(int level) const;
  /// The primary method at @p hit for the side with unit normal @p n, at @p level. @p pathLength
  /// is the distance from the camera along the path (for the footprint clamp; 0 = none).
  IrradianceRecord computeRecord(const Hit& hit, const Vec3& n, int level, Sampler& sampler, float pathLength = 0.0f) const;
  /// The shared cache (after preprocess()).
  IrradianceCache& cache() { return *cache_; }
  const IrradianceCache& cache() const { return *cache_; }
  /// The settings and the scene's lighting setup that decide the records' values, as text
  /// (what the cache file must match).
  std::string settingsText() const;
  /// True for the lights whose emission the cache gathers (large area lights), by LightSet index.
  const std::vector<uint8_t>& gatheredLights() const { return gathered_; }

 protected:
  /// Radiance along camera ray @p ray: radiance() from level 0, the two-pass render's private records counted.
  Color LiFrom(const Ray& ray, const Hit* first, Sampler& sampler, SampleInfo* info, uint64_t& rays) const override;

 private:
  struct Context;
  enum class RayKind : uint8_t;
  struct FirstVertex;
  /// Radiance along @p ray whose first hit is path vertex (and cache level) @p level, the next hits
  /// @p level + 1, ... (mirrors, glass, glossy samples); @p pathLength is the distance from the
  /// camera to the ray's origin along the path (for the footprint clamp). @p first, if given,
  /// receives the first hit and the first-shot term there. @p known, if given, is the ray's closest
  /// hit, already traced (and counted) by the caller.
  Color radiance(Ray ray, int level, RayKind kind, float pathLength, Sampler& sampler, Context& ctx,
                 FirstVertex* first, SampleInfo* info, const Hit* known = nullptr) const;
  /// Outgoing radiance at a non-delta vertex; @p firstShot, if given, receives its first-shot term.
  Color shade(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf, int level, bool cameraVertex,
              float pathLength, Sampler& sampler, Context& ctx, Color* firstShot = nullptr) const;
  Color irradiance(const Hit& hit, const Vec3& n, int level, float pathLength, Sampler& sampler, Context& ctx) const;
  /// Whether a vertex at @p p samples the luminaires' lights (LuminaireBoxes::innerWanted): a box around it is seen as
  /// it is, since the cache's own rays never enter one to suppress it (luminaires.cpp). False without luminaires.
  bool innerLightsAt(const Vec3& p) const {
    return luminaires_ && scene_->luminaires().innerWanted(scene_->luminaires().containing(p), false);
  }
  /// The zone of a record at @p p (IrradianceRecord::zone): 1 + the luminaire box holding it, 0 outside every box
  /// (always 0 without luminaires). Inside a box its light reflected there is indirect light, outside its exit light
  /// is direct: a record must not serve the other side (luminaires.cpp).
  int32_t zoneOf(const Vec3& p) const { return luminaires_ ? int32_t(scene_->luminaires().containing(p) + 1) : 0; }
  /// Radiance along a record's or glossy ray @p ray (its throughput @p beta) whose hit @p hit, path vertex @p vertex,
  /// lies in a luminaire's box it entered from outside: the path continuation from there, the exit light and the
  /// luminaire's lights counted by the shaded point's NEE (luminaires.cpp). @p first: as radiance()'s.
  Color enteredLuminaire(const Ray& ray, const Hit& hit, const BSDF& bsdf, const Color& beta, int vertex,
                         Sampler& sampler, Context& ctx, FirstVertex* first) const;
  IrradianceRecord gather(const Hit& hit, const Vec3& n, int level, float pathLength, Sampler& sampler, Context& ctx) const;
  /// True if gather() samples the lit patches (a table, patch emitters, patchNee > 0).
  bool patchNeeOn() const;
  /// Patch NEE at the record point (hit, side @p n) against @p cells hemisphere rays: the
  /// MIS-weighted irradiance of its samples (W/m²), drawn from the sampler keyed by @p key.
  Color patchNeeIrradiance(const Hit& hit, const Vec3& n, int cells, uint64_t key, Context& ctx) const;
  /// MIS weight of a hemisphere ray (one of @p cells, direction density cosθ/π) that met @p y
  /// from the record at @p x with normal @p n, against patchNeeIrradiance()'s samples.
  float hemisphereWeight(const Vec3& x, const Vec3& n, int cells, const Hit& y, float cosTheta) const;
  std::unique_ptr<IrradianceCache> makeCache() const;
  /// cache_ rebuilt from its records in order (as reading a cache file builds it), each first passed to @p edit
  /// (level, index in the level, record), then frozen.
  void rebuildCache(const std::function<void(int, size_t, IrradianceRecord&)>& edit);
  /// preprocess() without the fill: lights, the empty cache, the cache file.
  void setup(const RenderScene& scene);
  /// setup() and, two-pass, the fill over @p camera's pixels (the render's own first camera samples of each).
  void fillFor(const RenderScene& scene, const CameraDesc& camera);
  /// Two-pass fill from the rays of tasks 0 .. @p tasks − 1, in that order. With several ranks
  /// (IntegratorOptions::comm) each rank traces the tasks comm.mine() deals to it and the batch's
  /// records are exchanged before the merge, so every rank merges the same records in the same order.
  void fill(size_t tasks, const RayTask& task);
  /// The records of one fill task, per level in the order it made them.
  using MadeRecords = std::vector<std::vector<IrradianceRecord>>;
  /// Sends made[i] and looked[i] (whether the task looked the cache up) for the tasks @p mine (batch offsets from task
  /// @p pos) to every rank and fills in the other ranks' tasks of the batch. Returns the first interrupt signal any
  /// rank reported (0: none; then @p made is incomplete).
  int exchangeRecords(Comm& comm, size_t pos, const std::vector<size_t>& mine, std::vector<MadeRecords>& made,
                      std::vector<uint8_t>& looked);

  IntegratorOptions options_;
  IrradianceCacheSettings settings_;
  FirstShotLighting firstShot_;           ///< built once per preprocess(); the continuation's too
  PathWalk continuation_;                 ///< traces the light past the last level
  LightSampler directLights_;             ///< NEE over the direct lights (and the lit patches)
  std::vector<uint8_t> gathered_;         ///< per light: emission gathered by the cache (large area lights)
  std::vector<uint8_t> direct_;           ///< per light: NEE / first-shot (the others)
  std::vector<uint8_t> directEvery_;      ///< direct_ but the luminaires' lights (a camera vertex outside their boxes)
  bool luminaires_ = false;               ///< the table's luminaires are sampled (IntegratorOptions::luminaires)
  std::vector<uint8_t> gatheredEmitter_;  ///< per emitter mesh: its light is gathered
  Vec3 boundsLo_{0.0f}, boundsHi_{1.0f};
  float pixelAngle_ = 0.0f;               ///< footprint of one pixel per metre of distance
  std::unique_ptr<IrradianceCache> cache_;
  bool frozen_ = false;                   ///< two-pass render: the shared cache is read-only
  bool pathOnMiss_ = false;               ///< after a two-pass fill: a miss takes one path (frozen, or over budget)
  int spreadEvery_ = 0;  ///< preprocessFor: about one level-0 record in this many is gathered twice (0: none)
  static constexpr uint64_t kSpreadSalt = 0x5eedf00du;
  uint64_t missSalt_ = 0;  ///< keyMissPaths(): a miss's path draws from the lookup's key and this (0: the sample's)
  uint64_t taskRayBudget_ = 0;            ///< preprocessRays' fill: rays per task before misses take paths (0: none)
  size_t loaded_ = 0;
  double fillSeconds_ = 0;
  uint64_t fillRays_ = 0;
  uint64_t fillRayLimit_ = 0;  ///< limitPreprocessRays(): the fill stops past it (0: none)
  double fillSecondsLimit_ = 0;  ///< limitPreprocessSeconds(): the fill stops past it, fit to render (0: none)
  size_t fillCutAt_ = 0, fillTasks_ = 0;  ///< IrradianceCacheStats::fillCutAt, fillPixels
  uint64_t madeRecords_ = 0, duplicateRecords_ = 0;  ///< IrradianceCacheStats::fillMade, fillDuplicates
  int fillRounds_ = 0;
  uint64_t exchangeBytes_ = 0;
  double exchangeSeconds_ = 0;
  mutable std::atomic<uint64_t> privateRecords_{0};
  mutable std::atomic<uint64_t> missPaths_{0};
};

}  // namespace firstshot
