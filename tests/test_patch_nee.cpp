// Lit first-shot patches sampled as light sources and the light tree in the path tracer
// (render/lights/light_sampler.h): sampling them changes the noise, never the mean (3σ, σ from the
// samples); the light tree's NEE agrees with NEE to every light; the irradiance cache's default
// continuation past its last bounce agrees with path tracing; images do not depend on threads.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/render_util.h"
#include "tests/shaded_room.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// Largest |mean(a) − mean(b)| / σ over the channels, σ combined from both images' pixel variances.
double meanZ(const Film& a, const Film& b, const std::string& label, double* relDiff = nullptr) {
  double z = 0;
  if (relDiff) *relDiff = 0;
  for (int c = 0; c < 3; ++c) {
    double ma, sa, mb, sb;
    test::imageMean(a, c, ma, sa);
    test::imageMean(b, c, mb, sb);
    const double se = std::hypot(sa, sb);
    fmt::print("  {} channel {}: {:.5f} vs {:.5f}, diff {:+.5f} ± {:.5f} ({:+.3f}%)\n", label, c, ma, mb, ma - mb, se,
               100.0 * (ma - mb) / mb);
    EXPECT_GT(se, 0.0) << label;
    z = std::max(z, std::abs(ma - mb) / se);
    if (relDiff) *relDiff = std::max(*relDiff, std::abs(ma - mb) / mb);
  }
  return z;
}

/// Mean over pixels and channels of the per-sample variance (the noise of one sample per pixel).
double meanVariance(const Film& f) {
  double v = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) {
      const Color c = f.variance(x, y);
      v += c.x + c.y + c.z;
    }
  return v / (3.0 * f.width() * f.height());
}

}  // namespace

TEST(PatchNee, HiddenLightSameMeanLessNoise) {
  const SceneDesc desc = test::shadedLightRoom(24);
  const RenderScene scene(desc, test::quickTable(desc));
  IntegratorOptions off;
  off.patchNee = PatchNee::Off;
  const int spp = 96;
  const auto b = test::renderPath(scene, off, spp, 2);
  for (PatchNee mode : {PatchNee::First, PatchNee::Every}) {
    IntegratorOptions on;
    on.patchNee = mode;
    const auto a = test::renderPath(scene, on, spp, 1);
    const std::string label = mode == PatchNee::First ? "patch NEE first vertex vs off" : "patch NEE every vertex vs off";
    EXPECT_EQ(a.stats.nonFinite + b.stats.nonFinite, 0u);
    EXPECT_LT(meanZ(a.film, b.film, label), 3.0) << label;
    const double ratio = meanVariance(b.film) / meanVariance(a.film);
    fmt::print("  per-sample variance, {}: {:.2f}\n", label, ratio);
    // Sampled at every vertex the lit patches must cut the noise; at the first vertex only the
    // gain is smaller (measured 1.2–1.6 here) and is reported, not asserted.
    if (mode == PatchNee::Every) {
      EXPECT_GT(ratio, 2.0) << "sampling the lit patches should cut the noise";
    }
  }
}

TEST(PatchNee, CornellSameMeanForBothStrategies) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 24;
  const RenderScene scene(desc, test::quickTable(desc));
  for (LightStrategy strategy : {LightStrategy::Tree, LightStrategy::All})
    for (PrimaryMode primary : {PrimaryMode::Exact, PrimaryMode::Patch}) {
      IntegratorOptions on, off;
      on.lightSampler = off.lightSampler = strategy;
      on.primary = off.primary = primary;
      off.patchNee = PatchNee::Off;
      on.patchNee = PatchNee::Every;
      const auto a = test::renderPath(scene, on, 64, 1);
      const auto b = test::renderPath(scene, off, 64, 2);
      const std::string label = fmt::format("cornell {} {}", strategy == LightStrategy::Tree ? "tree" : "all",
                                            primary == PrimaryMode::Exact ? "exact" : "patch");
      EXPECT_LT(meanZ(a.film, b.film, label), 3.0) << label;
    }
}

TEST(LightTreeNee, AgreesWithNeeToEveryLight) {
  SceneDesc desc = loadScene(test::source("scenes/many-lights.json"));
  desc.camera.width = 24;
  desc.camera.height = 18;
  const RenderScene scene(desc);
  IntegratorOptions tree, all;
  tree.lightSampler = LightStrategy::Tree;
  all.lightSampler = LightStrategy::All;
  const auto a = test::renderPath(scene, tree, 128, 1);
  const auto b = test::renderPath(scene, all, 32, 2);
  EXPECT_LT(meanZ(a.film, b.film, "many-lights tree vs all"), 3.0);
}

/// Two rooms side by side, a wall between them: the camera's room has one light, the other 32.
/// A light tree blind to the wall spends most shadow rays on the other room; weighted by the
/// visibility estimated per grid cell it does not: same mean (3σ), far less noise.
TEST(LightTreeNee, VisibilityFactorsSameMeanLessNoise) {
  std::string lights = R"({"type": "point", "position": [1.5, 2.5, 1.5], "power": 40})";
  for (int i = 0; i < 32; ++i)
    lights += fmt::format(R"(, {{"type": "point", "position": [{}, 2.5, {}], "power": 40}})", 3.4 + 0.35 * (i % 8),
                          0.4 + 0.7 * (i / 8));
  const SceneDesc desc = test::sceneFromJson(fmt::format(R"({{
    "materials": {{"wall": {{"type": "diffuse", "albedo": 0.6}}}},
    "shapes": [
      {{"type": "box", "min": [0, 0, 0], "max": [6, 3, 3], "material": "wall", "flip_normals": true}},
      {{"type": "box", "min": [2.95, 0, 0], "max": [3.05, 3, 3], "material": "wall"}}
    ],
    "lights": [{}],
    "camera": {{"position": [0.3, 1.5, 0.3], "look_at": [2.5, 0.8, 2.5], "fov_y": 70, "resolution": [24, 24]}},
    "settings": {{"patch_size": 0.25, "max_depth": 4}}
  }})", lights));
  const RenderScene scene(desc);
  IntegratorOptions blind, seeing;
  blind.lightSampler = seeing.lightSampler = LightStrategy::Tree;
  blind.maxDepth = seeing.maxDepth = 4;
  blind.lightVisibility = false;
  const auto a = test::renderPath(scene, seeing, 128, 1);
  const auto b = test::renderPath(scene, blind, 128, 2);
  EXPECT_LT(meanZ(a.film, b.film, "visibility-weighted tree vs blind tree"), 3.0);
  const double ratio = meanVariance(b.film) / meanVariance(a.film);
  fmt::print("  per-sample variance, blind / visibility-weighted: {:.2f}\n", ratio);
  EXPECT_GT(ratio, 2.0) << "the other room's lights should rarely be chosen";
}

TEST(PatchNee, ImageDoesNotDependOnThreads) {
  const SceneDesc desc = test::shadedLightRoom(24);
  const RenderScene scene(desc, test::quickTable(desc));
  IntegratorOptions io;
  io.lightSampler = LightStrategy::Tree;
  io.patchNee = PatchNee::Every;
  const auto one = test::renderPath(scene, io, 4, 5, 1);
  const auto two = test::renderPath(scene, io, 4, 5, 2);
  for (int y = 0; y < one.film.height(); ++y)
    for (int x = 0; x < one.film.width(); ++x) ASSERT_EQ(one.film.mean(x, y), two.film.mean(x, y)) << x << "," << y;
}

/// The cache at its defaults continues paths past its last bounce: its image mean agrees with
/// path tracing within 3σ, where a cache that stops there (ambient 0) does not; with no cached
/// bounce the continuation alone is path tracing.
/// The Cornell box framed without the light (pixels that show the light are noise at 4 spp);
/// the cache's σ comes from independent caches (seeds), since its records correlate pixels.
TEST(IrradianceCacheContinuation, DefaultsMatchPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("every default irradiance-cache test (they continue paths past the cache)");
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.lookAt = Vec3d(0.278, 0.17, 0.0);
  desc.camera.fovYDeg = 28;
  desc.camera.width = desc.camera.height = 20;
  const RenderScene scene(desc, test::quickTable(desc));
  IntegratorOptions io;
  const auto path = test::renderPath(scene, io, 1024, 1);
  auto cacheMeans = [&](const IrradianceCacheSettings& settings, double& mean, double& se) {
    const int runs = 8;
    std::vector<double> m;
    for (int r = 0; r < runs; ++r) {
      IrradianceCacheIntegrator ic(io, settings);
      ic.preprocess(scene);
      const auto run = test::renderWith(ic, scene, 4, 10 + r);
      EXPECT_EQ(run.stats.nonFinite, 0u);
      double mc = 0, sc;
      for (int c = 0; c < 3; ++c) {
        double v;
        test::imageMean(run.film, c, v, sc);
        mc += v / 3.0;
      }
      m.push_back(mc);
    }
    mean = 0;
    for (double v : m) mean += v / runs;
    double var = 0;
    for (double v : m) var += (v - mean) * (v - mean) / (runs - 1);
    se = std::sqrt(var / runs);
  };
  double pm = 0, pv = 0;
  for (int c = 0; c < 3; ++c) {
    double m, s;
    test::imageMean(path.film, c, m, s);
    pm += m / 3.0, pv += s * s / 9.0;
  }
  double icMean, icSe;
  cacheMeans(IrradianceCacheSettings(), icMean, icSe);
  const double se = std::sqrt(icSe * icSe + pv);
  fmt::print("  irradiance cache {:.5f} ± {:.5f}, path {:.5f} ± {:.5f}: {:+.3f}% (3σ = {:.3f}%)\n", icMean, icSe, pm,
             std::sqrt(pv), 100.0 * (icMean - pm) / pm, 300.0 * se / pm);
  EXPECT_LT(std::abs(icMean - pm), 3.0 * se);

  // No cached bounce at all: every vertex's indirect light is the continuation, i.e. path tracing.
  // No records either, so pixels are independent and the film's own variances give σ.
  IrradianceCacheSettings none;
  none.bounces = 0;
  IrradianceCacheIntegrator continuation(io, none);
  continuation.preprocess(scene);
  const auto cont = test::renderWith(continuation, scene, 256, 3);
  EXPECT_LT(meanZ(cont.film, path.film, "continuation only vs path"), 3.0);

  IrradianceCacheSettings truncated;
  truncated.pathContinuation = false;  // ambient 0 past the last bounce
  double oldMean, oldSe;
  cacheMeans(truncated, oldMean, oldSe);
  fmt::print("  irradiance cache with ambient 0: {:.5f} ± {:.5f}: {:+.3f}%\n", oldMean, oldSe, 100.0 * (oldMean - pm) / pm);
  EXPECT_GT(std::abs(oldMean - pm), 3.0 * std::sqrt(oldSe * oldSe + pv)) << "the light past the last bounce must matter here";
}
