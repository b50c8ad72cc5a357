// --max-depth means the same in every integrator: at max depth 1, 2 and 3 the image mean
// of each integrator that takes it — the irradiance cache, light tracing, BDPT, the bundle — agrees
// with the path tracer's within 3σ on small renders: the Cornell box (looking a little down, its
// small area light out of view), the many-lights room (64 point lights), light tracing's mirror-and-
// glass scene and the mixed-lights scene (glossy wall; directional, spot, point and area lights),
// each without and with a first-shot table (the same table for both integrators); the bundle on the
// scenes its patch discretisation does not bias (below). What counts as a bounce:
// docs/irradiance-cache.md, "What --max-depth counts".
//
// σ of an image mean is estimated from independent repetitions: 12 renders with seeds 1..12, each
// render's grey image mean one sample, σ = their standard deviation / √12; the comparison takes
// σ = √(σ_a² + σ_b²). Repetitions rather than per-pixel variances, because an integrator's pixels
// are not independent within a render: the cache's records are shared by all pixels (each repetition
// gets a cache of its own, filled from that seed's camera samples), light tracing and BDPT splat a
// particle into several pixels, the bundle's iterations share one transfer (a fresh one per seed).
// Before the fix the cache was off by up to +130% (many-lights, depth 1) and 27σ at depth 3, BDPT in
// table mode by +22.6% on mirror-glass at depth 1, the bundle by +31% on the box at depth 1.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/bundle/integrator.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/block_compare.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

#ifdef FIRSTSHOT_UNDER_SANITIZERS
// Under ASan+UBSan every case runs once more cheaply, for memory and UB only: two runs of one sample.
constexpr bool kStatistics = false;
constexpr int kRuns = 2;
#else
constexpr bool kStatistics = true;
constexpr int kRuns = 12;  ///< independent repetitions per estimate
#endif

using test::Estimate;
using test::greyImageMean;

/// The irradiance cache's settings in these tests: fewer hemisphere samples than the default (the
/// bounces are counted the same way), B = 3 levels of records, or B = 1 so that the path
/// continuation past the last level is what depths 2 and 3 add.
IrradianceCacheSettings cacheSettings(int bounces) {
  IrradianceCacheSettings s;
  s.samples = 64;
  s.bounces = bounces;
  return s;
}

/// kRuns renders of @p spp samples with seeds 1..kRuns: the mean of their image means and its σ.
/// @p name: a makeIntegrator name, or "irradiance-cache/B" for the cache with B levels.
Estimate estimate(const std::string& name, const RenderScene& scene, int depth, int spp) {
  IntegratorOptions io;
  io.maxDepth = depth;
  test::Moments m;
  std::unique_ptr<Integrator> shared;
  for (int r = 0; r < kRuns; ++r) {
    const uint64_t seed = 1 + uint64_t(r);
    std::unique_ptr<Integrator> own;
    const Integrator* integrator = nullptr;
    if (name.starts_with("irradiance-cache/")) {  // a cache of its own per seed, filled from that seed's samples
      IrradianceCacheSettings s = cacheSettings(std::stoi(name.substr(name.find('/') + 1)));
      s.seed = seed;
      own = std::make_unique<IrradianceCacheIntegrator>(io, s);
      own->preprocess(scene);
      integrator = own.get();
    } else if (name == "bundle") {  // a fresh transfer per seed; iterations from depth − 1 on, whose
      // orders ≤ depth − 1 are complete (BundleTransfer: order b is from iteration b on), so no start-up bias
      auto b = std::make_unique<BundleIntegrator>(io);
      BundleSettings bs;
      bs.resolution = 64;
      b->setSettings(bs);
      b->preprocess(scene);
      const Camera camera(scene.desc().camera);
      Film film(camera.width(), camera.height());
      RenderOptions ro;
      ro.spp = kStatistics ? spp : 1, ro.firstSample = std::max(0, depth - 1), ro.seed = seed;
      EXPECT_EQ(render(*b, camera, film, ro).nonFinite, 0u) << name;
      m.add(greyImageMean(film));
      continue;
    } else {  // the others keep no state between renders
      if (!shared) shared = test::preprocessedIntegrator(name, io, scene);
      integrator = shared.get();
    }
    m.add(test::renderedGreyMean(*integrator, scene, kStatistics ? spp : 1, seed, name));
  }
  return {m.mean(), m.se()};
}

struct Case {
  std::string name;
  std::function<SceneDesc()> scene;
  bool table = false;
};

/// The scene of @p c, with a first-shot table (Embree item buffers, R = 64) if asked: path tracing
/// and the integrator under test read the same scene and table.
const RenderScene& sceneOf(const Case& c) {
  static std::map<std::string, std::unique_ptr<RenderScene>> scenes;
  auto& slot = scenes[c.name];
  if (!slot) {
    const SceneDesc d = c.scene();
    if (c.table) {
      PreprocessOptions po = defaultOptions(d);
      po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
      slot = std::make_unique<RenderScene>(d, preprocessScene(d, po));
      EXPECT_FALSE(slot->firstShot()->replacedLights.empty()) << c.name;
    } else {
      slot = std::make_unique<RenderScene>(d, d.settings.patchSize);
    }
  }
  return *slot;
}

/// Path tracing's estimate for @p c at @p depth, computed once.
Estimate pathReference(const Case& c, int depth) {
  static std::map<std::string, Estimate> done;
  const std::string key = fmt::format("{} {}", c.name, depth);
  auto it = done.find(key);
  if (it == done.end()) it = done.emplace(key, estimate("path", sceneOf(c), depth, 64)).first;
  return it->second;
}

/// @p name at max depth 1, 2, 3 (up to @p lastDepth) against path tracing on @p c, @p spp samples per run.
void expectDepthsAgree(const std::string& name, const Case& c, int spp, int lastDepth = 3) {
  const RenderScene& scene = sceneOf(c);
  for (int depth = 1; depth <= lastDepth; ++depth) {
    const auto start = std::chrono::steady_clock::now();
    const Estimate ref = pathReference(c, depth), e = estimate(name, scene, depth, spp);
    const double sigma = std::hypot(ref.se, e.se), z = sigma > 0 ? (e.mean - ref.mean) / sigma : 0.0;
    fmt::print("{} on {}, max depth {}: {:.5f} ± {:.5f} against path {:.5f} ± {:.5f}: {:+.2f}% ({:+.2f}σ), {:.1f} s\n",
               name, c.name, depth, e.mean, e.se, ref.mean, ref.se, 100 * (e.mean / ref.mean - 1), z,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (!kStatistics) continue;
    EXPECT_LT(std::abs(z), 3.0) << name << " on " << c.name << ", max depth " << depth;
    // The test must be able to see a bounce too many or too few (each adds ≥ 5% on these scenes).
    EXPECT_LT(sigma, 0.015 * ref.mean) << name << " on " << c.name << ", max depth " << depth << ": too noisy to test";
  }
}

SceneDesc shipped(const std::string& name, int width, int height) {
  SceneDesc d = loadScene(test::source("scenes/" + name + ".json"));
  d.camera.width = width, d.camera.height = height;
  return d;
}

/// The Cornell box looking a little down: its light out of view (the pixels that see it carry
/// most of the variance of an image mean and none of the bounces).
SceneDesc cornell() {
  SceneDesc d = shipped("cornell", 24, 24);
  d.camera.lookAt.y = 0.12;
  return d;
}
SceneDesc room() { return shipped("many-lights", 24, 18); }
SceneDesc mirrorGlass() {
  SceneDesc d = test::mirrorGlassScene();
  d.camera.width = 24, d.camera.height = 18;
  return d;
}

/// A glossy wall and every kind of light: directional, spot, point and area.
SceneDesc mixed() {
  SceneDesc d = test::mixedLightsScene();
  d.camera.width = 24, d.camera.height = 18;
  return d;
}

/// A closed box [−1, 1]³ of albedo 0.5 whose walls emit 1 W/(m² sr), seen from inside: at max depth D
/// every pixel is Σ_{i ≤ D} 0.5^i, and the bundle's uniform walls have no discretisation error.
SceneDesc box() {
  return test::sceneFromJson(R"({
    "camera": {"position": [0.1, -0.2, 0.3], "look_at": [0.5, 0.4, -1], "fov_y": 70, "resolution": [16, 16]},
    "materials": {"wall": {"type": "diffuse", "albedo": 0.5, "emission": 1}},
    "shapes": [{"type": "box", "material": "wall", "min": [-1, -1, -1], "max": [1, 1, 1], "flip_normals": true}],
    "settings": {"patch_size": 0.5}})");
}

const Case kBox{"emitting box", box, false};
const Case kCornell{"cornell", cornell, false}, kCornellTable{"cornell with a table", cornell, true};
const Case kRoom{"many-lights", room, false}, kRoomTable{"many-lights with a table", room, true};
const Case kMirrors{"mirror-glass", mirrorGlass, false}, kMirrorsTable{"mirror-glass with a table", mirrorGlass, true};
const Case kMixed{"mixed lights", mixed, false}, kMixedTable{"mixed lights with a table", mixed, true};

}  // namespace

// The bundle against path tracing where its patch discretisation is exact (the uniformly emitting
// box) or below the noise (cornell with a table); the many-lights room is off by 2–6% at every depth
// (patch-level first-shot light, docs/bundle.md), so it is not among them. On mirror-glass only depth
// 1: the camera's mirror counts as a bounce (the wall seen in it shows no light), while the transfer
// carries no light through mirrors and glass at all.
TEST(MaxDepth, BundleCountsBouncesLikePathTracing) {
  for (const Case& c : {kBox, kCornellTable}) expectDepthsAgree("bundle", c, 24);
  expectDepthsAgree("bundle", kMirrorsTable, 24, 1);
}

TEST(MaxDepth, IrradianceCacheCountsBouncesLikePathTracing) {
  for (const Case& c : {kRoom, kCornell, kMirrors, kMixed}) expectDepthsAgree("irradiance-cache/3", c, 2);
  expectDepthsAgree("irradiance-cache/1", kCornell, 2);
}

TEST(MaxDepth, IrradianceCacheOnTableCountsBouncesLikePathTracing) {
  for (const Case& c : {kRoomTable, kCornellTable, kMirrorsTable, kMixedTable}) expectDepthsAgree("irradiance-cache/3", c, 2);
  expectDepthsAgree("irradiance-cache/1", kCornellTable, 2);
}

TEST(MaxDepth, LightTracingCountsBouncesLikePathTracing) {
  for (const Case& c : {kRoom, kCornell, kMirrors, kMixed}) expectDepthsAgree("light", c, 16);
}

TEST(MaxDepth, LightTracingOnTableCountsBouncesLikePathTracing) {
  for (const Case& c : {kRoomTable, kCornellTable, kMirrorsTable, kMixedTable}) expectDepthsAgree("light", c, 16);
}

TEST(MaxDepth, BdptCountsBouncesLikePathTracing) {
  for (const Case& c : {kRoom, kCornell, kMirrors, kMixed}) expectDepthsAgree("bdpt", c, 8);
}

TEST(MaxDepth, BdptOnTableCountsBouncesLikePathTracing) {
  for (const Case& c : {kRoomTable, kCornellTable, kMirrorsTable, kMixedTable}) expectDepthsAgree("bdpt", c, 8);
}
