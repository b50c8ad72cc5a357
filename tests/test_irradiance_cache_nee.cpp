// Next-event estimation in the irradiance cache: its direct lights sampled by a light tree agree
// with NEE to every direct light (same mean within 3σ, σ from the per-seed records; the variance
// is reported), and the lit first-shot patches sampled at the record point and combined with the
// hemisphere rays by MIS leave the record's mean unchanged (3σ, tight enough that counting the
// lit patches twice fails); two-pass images do not depend on the number of threads.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <chrono>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/render_util.h"
#include "tests/shaded_room.h"
#include "tests/stats.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// One bounce, nothing past it (ambient 0), no footprint clamp: a record's E is the light its
/// hemisphere rays gather from the surfaces they hit (their direct and first-shot light).
IrradianceCacheSettings oneBounce(int samples, float patchNee) {
  IrradianceCacheSettings s;
  s.samples = samples;
  s.bounces = 1;
  s.pathContinuation = false;
  s.footprintMin = 0.0f;
  s.footprintMax = std::numeric_limits<float>::infinity();
  s.patchNee = patchNee;
  return s;
}

/// The surface hit straight below @p above (looking down).
Hit hitBelow(const RenderScene& scene, const Vec3& above) {
  Hit h;
  EXPECT_TRUE(scene.intersect(Ray(above, Vec3(0, -1, 0)), h));
  return h;
}

struct Records {
  test::RunningStats E;  ///< channel mean of E, W/m²
  double seconds = 0;
};

/// @p count records at @p hit (normal +y), one per seed.
Records records(const IrradianceCacheIntegrator& ic, const Hit& hit, int count, uint64_t seed) {
  Records r;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < count; ++i) {
    Sampler s(seed, uint64_t(i), 0);
    const IrradianceRecord rec = ic.computeRecord(hit, Vec3(0, 1, 0), 0, s);
    r.E.add((rec.E.x + rec.E.y + rec.E.z) / 3.0);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

/// |mean(a) − mean(b)| in combined standard errors, printed with @p label.
double zScore(const Records& a, const Records& b, const std::string& label) {
  const double se = std::hypot(a.E.standardError(), b.E.standardError());
  fmt::print("  {}: E {:.5f} ± {:.5f} vs {:.5f} ± {:.5f} (z = {:.2f}); per-record variance {:.3e} vs {:.3e}; "
             "{:.2f} s vs {:.2f} s\n",
             label, a.E.mean, a.E.standardError(), b.E.mean, b.E.standardError(), std::abs(a.E.mean - b.E.mean) / se,
             a.E.variance(), b.E.variance(), a.seconds, b.seconds);
  EXPECT_GT(se, 0.0) << label;
  return std::abs(a.E.mean - b.E.mean) / se;
}

/// scenes/many-lights.json at @p width × @p height pixels.
SceneDesc manyLights(int width, int height) {
  SceneDesc desc = loadScene(test::source("scenes/many-lights.json"));
  desc.camera.width = width, desc.camera.height = height;
  return desc;
}

/// The renderer's options with light strategy @p strategy.
IntegratorOptions sampler(LightStrategy strategy) {
  IntegratorOptions io;
  io.lightSampler = strategy;
  return io;
}

}  // namespace

/// The office of many point lights: the cache's direct light by a light tree (one light per
/// vertex) against NEE to every light, through the direct light of the surfaces a record's
/// hemisphere rays hit. Same mean; the variance per record is reported (one light per vertex is
/// noisier per record, and much cheaper).
TEST(IrradianceCacheNee, LightTreeDirectAgreesWithNeeToEveryLight) {
  const RenderScene scene(manyLights(16, 12));
  const IntegratorOptions tree = sampler(LightStrategy::Tree), all = sampler(LightStrategy::All);
  IrradianceCacheIntegrator a(tree, oneBounce(128, 0.0f)), b(all, oneBounce(128, 0.0f));
  a.preprocess(scene);
  b.preprocess(scene);
  const Hit hit = hitBelow(scene, Vec3(3.0f, 1.0f, 4.5f));
  const Records ra = records(a, hit, 400, 1), rb = records(b, hit, 100, 2);
  EXPECT_GT(ra.E.mean, 0.0);
  EXPECT_LT(zScore(ra, rb, "many-lights record, tree vs all"), 3.0);
}

/// Whole images: with the tree and with NEE to every light, the many-lights office agrees in mean
/// (no cached bounce, so the pixels are independent and σ comes from them). Camera-visible points
/// take NEE to every direct light either way; the continued paths differ.
TEST(IrradianceCacheNee, LightTreeImageAgreesWithNeeToEveryLight) {
  const RenderScene scene(manyLights(24, 18));
  const IntegratorOptions tree = sampler(LightStrategy::Tree), all = sampler(LightStrategy::All);
  // No cached bounce: the image is direct light at the camera vertex plus path-traced indirect light.
  IrradianceCacheSettings s;
  s.bounces = 0;
  IrradianceCacheIntegrator a(tree, s), b(all, s);
  a.preprocess(scene);
  b.preprocess(scene);
  const auto ia = test::renderWith(a, scene, 64, 1), ib = test::renderWith(b, scene, 16, 2);
  for (int c = 0; c < 3; ++c) {
    double ma, sa, mb, sb;
    test::imageMean(ia.film, c, ma, sa);
    test::imageMean(ib.film, c, mb, sb);
    fmt::print("  many-lights image channel {}: tree {:.5f} ± {:.5f}, all {:.5f} ± {:.5f}\n", c, ma, sa, mb, sb);
    EXPECT_LT(std::abs(ma - mb), 3.0 * std::hypot(sa, sb)) << "channel " << c;
  }
}

/// Patch NEE in the primary method against the hemisphere rays alone, at a floor point beside the
/// shaded light and one under it: same mean at every NEE rate (the MIS weights of the two
/// techniques sum to one). Here E is first-shot light only, so counting it twice (no MIS) would
/// double the mean: the test requires 3σ below a quarter of E, so that it would fail then.
TEST(IrradianceCacheNee, PatchNeeKeepsTheRecordMean) {
  const SceneDesc desc = test::shadedLightRoom(16);
  const RenderScene scene(desc, test::quickTable(desc));
  IrradianceCacheIntegrator off(IntegratorOptions{}, oneBounce(128, 0.0f));
  off.preprocess(scene);
  for (const Vec3 p : {Vec3(1.0f, 1.0f, 1.2f), Vec3(2.0f, 1.0f, 2.1f)}) {
    const Hit hit = hitBelow(scene, p);
    const Records rOff = records(off, hit, 4000, 5);
    ASSERT_GT(rOff.E.mean, 0.0);
    for (float rate : {0.25f, 1.0f, 4.0f}) {
      IrradianceCacheIntegrator on(IntegratorOptions{}, oneBounce(128, rate));
      on.preprocess(scene);
      const Records rOn = records(on, hit, 400, 4);
      const std::string label = fmt::format("point ({}, {}), patch NEE {} per ray vs off", p.x, p.z, rate);
      EXPECT_LT(zScore(rOn, rOff, label), 3.0) << label;
      EXPECT_LT(3.0 * std::hypot(rOn.E.standardError(), rOff.E.standardError()), 0.25 * rOff.E.mean)
          << label << ": too noisy to see a double count";
    }
  }
}

/// A two-pass cache with the light tree and patch NEE renders the same image on 1 and 2 threads.
TEST(IrradianceCacheNee, TwoPassImageDoesNotDependOnThreads) {
  const SceneDesc desc = test::shadedLightRoom(16);
  const RenderScene scene(desc, test::quickTable(desc));
  auto run = [&](int threads) {
    IrradianceCacheSettings s = oneBounce(64, 1.0f);
    s.bounces = 2;
    s.pathContinuation = true;
    s.twoPass = true;
    s.threads = threads;
    s.seed = 7;
    IntegratorOptions io;
    io.lightSampler = LightStrategy::Tree;
    IrradianceCacheIntegrator ic(io, s);
    ic.preprocess(scene);
    return test::renderWith(ic, scene, 2, 7, threads);
  };
  const auto one = run(1), two = run(2);
  for (int y = 0; y < one.film.height(); ++y)
    for (int x = 0; x < one.film.width(); ++x) ASSERT_EQ(one.film.mean(x, y), two.film.mean(x, y)) << x << "," << y;
}
