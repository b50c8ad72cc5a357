// Luminaires in the irradiance cache (render/integrators/irradiance_cache/luminaires.cpp): their light is direct light
// at every shaded point (exit patches, specular light, their lights where the path tracer samples them), and a
// record's or glossy ray that enters a box meets none of it there. Against light tracing with their lights as lights,
// every 8×8 block within 3σ, σ from fills of different seeds (a fill's records freeze their noise into every pass of
// it), on the bulb in an open metal bowl and the filament in a clear glass envelope (tests/hidden_lights_scenes.h).
// One cached bounce: the rules are the same at every level, and deeper levels add the cache's interpolation error,
// which is not in question here. And its records are less noisy than with the luminaires' lights taken as lights,
// whose light the records' rays then find by chance (a block's spread between fills 3–25×). Also: which luminaires
// the cache takes (those whose box holds glass, a mirror or a glossy surface), and next-event estimation's choice of
// an exit patch against the probability it reports.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>

#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/block_compare.h"
#include "tests/hidden_lights_scenes.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// Per 8×8 block gray means of @p fills renders of @p scene by the irradiance cache (one cached bounce, @p spp samples
/// per pixel), each with its own fill (seeds 100, 101, ...).
std::vector<test::Moments> cacheBlocks(const RenderScene& scene, bool luminaires, int fills, int spp) {
  IntegratorOptions io;
  io.maxDepth = 32;  // as the exit distribution, which holds every bounce inside the box
  io.luminaires = luminaires;
  const Camera camera(scene.desc().camera);
  std::vector<test::Moments> blocks(size_t((camera.width() + 7) / 8) * size_t((camera.height() + 7) / 8));
  for (int r = 0; r < fills; ++r) {
    IrradianceCacheSettings s;
    s.bounces = 1;
    s.seed = 100 + uint64_t(r);
    IrradianceCacheIntegrator cache(io, s);
    cache.preprocess(scene);
    Film film(camera.width(), camera.height());
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = s.seed;
    render(cache, camera, film, ro);
    test::addBlockMeans(film, blocks);
  }
  return blocks;
}

/// The cache with the luminaires against light tracing without them (@p refPasses); with @p fills ≥ 8 also its
/// spread between fills against the cache's with the luminaires' lights as lights: the median block's variance
/// ratio above 4. (Were the two as noisy, a block's ratio of two 8-fill variances would exceed 4 with probability
/// 0.04, F(7, 7); half of the 12 blocks doing so, about 4·10⁻⁶.)
void expectCacheAgrees(const std::string& name, const SceneDesc& d, int fills, int spp, int refPasses) {
  if (!test::kCompareBlocks) fills = 1, spp = std::min(spp, 2);  // memory and UB only (block_compare.h)
  const RenderScene scene = test::withLuminaireTable(d);
  ASSERT_FALSE(scene.firstShot()->luminaires.empty()) << name << ": no luminaire found";
  IntegratorOptions io;
  io.maxDepth = 32;
  io.luminaires = false;
  auto ref = makeIntegrator("light", io);
  ref->preprocess(scene);
  const std::vector<test::Moments> on = cacheBlocks(scene, true, fills, spp);
  test::expectBlocksAgree(name + ", the cache with the luminaires against light tracing without", on,
                          test::blockMeans(*ref, scene, refPasses, 2));
  if (fills < 8) return;
  const std::vector<test::Moments> off = cacheBlocks(scene, false, fills, spp);
  std::vector<double> ratio;
  for (size_t k = 0; k < on.size(); ++k) ratio.push_back(std::pow(off[k].se() / on[k].se(), 2.0));
  std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
  const double median = ratio[ratio.size() / 2];
  fmt::print("{}: the blocks' variance between fills, lights as lights over luminaires: median {:.1f}\n", name, median);
  EXPECT_GT(median, 4.0) << name << ": the luminaires' light taken at every shaded point makes records less noisy";
}

}  // namespace

TEST(LuminaireCache, GlassBulb) { expectCacheAgrees("glass bulb", test::glassBulb(), 8, 16, 300); }

TEST(LuminaireCache, BowlLamp) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireCache.GlassBulb");
  expectCacheAgrees("bowl lamp", test::bowlLamp(), 8, 8, 200);
}

// The open box of grey diffuse walls holds no glass or gloss: the cache takes its light as a light, the same image as
// with --luminaires off (IrradianceCacheIntegrator::holdsNonLambertian).
TEST(LuminaireCache, LambertianBoxTakenAsItsLights) {
  const RenderScene scene = test::withLuminaireTable(test::openBox());
  ASSERT_FALSE(scene.firstShot()->luminaires.empty());
  EXPECT_FALSE(IrradianceCacheIntegrator::holdsNonLambertian(scene, scene.firstShot()->luminaires[0]));
  std::vector<double> film[2];
  for (int on = 0; on < 2; ++on) {
    IntegratorOptions io;
    io.luminaires = on == 1;
    IrradianceCacheIntegrator cache(io);
    cache.preprocess(scene);
    film[on] = test::filmValues(test::renderWith(cache, scene, 2).film);
  }
  EXPECT_EQ(film[0], film[1]);
}

// A luminaire the cache does not take leaves its small area light a light like any other small one: direct light at
// every shaded point, never gathered by the records' rays (the table keeps it, so it is not "replaced"; gathered, a
// 2 cm bulb is met by those rays by chance and its light came out 30–50% low where records see it, in blotches).
TEST(LuminaireCache, SmallLightOfALuminaireNotTakenIsDirectLight) {
  FIRSTSHOT_STATISTICS_ONLY("LuminaireCache.GlassBulb");
  SceneDesc d = test::openBox(true);  // looking at the floor and wall the opening lights
  d.camera.position = Vec3d(0.3, 1.3, 0.3);
  d.camera.lookAt = Vec3d(1.4, 0.3, 1.9);
  const RenderScene scene = test::withLuminaireTable(d);
  ASSERT_FALSE(scene.firstShot()->luminaires.empty());
  ASSERT_FALSE(IrradianceCacheIntegrator::holdsNonLambertian(scene, scene.firstShot()->luminaires[0]));
  IrradianceCacheIntegrator cache{IntegratorOptions()};
  cache.preprocess(scene);
  for (uint8_t gathered : cache.gatheredLights()) EXPECT_EQ(gathered, 0) << "a small light gathered by the records";
  IntegratorOptions io;
  io.maxDepth = 32;
  io.luminaires = false;
  auto ref = makeIntegrator("light", io);
  ref->preprocess(scene);
  test::expectBlocksAgree("open box, a small area light: the cache against light tracing", cacheBlocks(scene, true, 8, 16),
                          test::blockMeans(*ref, scene, 400, 2));
}

// The cache takes the luminaires only where every one holds glass, a mirror or a glossy surface: the shipped fixture
// room's coves and fabric shades (Lambertian alone) render as with --luminaires off, byte for byte; the bowl lamp's
// metal bowl is taken.
TEST(LuminaireCache, CliKeepsTheLuminairesThatHoldGlassOrGloss) {
#ifdef FIRSTSHOT_UNDER_SANITIZERS
  GTEST_SKIP() << "two tables at the defaults: the Release build's";
#endif
  const std::string dir = test::tempDir(), pre = FIRSTSHOT_PREPROCESS_EXE, render = FIRSTSHOT_RENDER_EXE;
  for (const auto& [scene, kept] : {std::pair{"fixture-room", false}, std::pair{"bowl-lamp-room", true}}) {
    const std::string file = test::source(std::string("scenes/") + scene + ".json"), fsd = dir + "/" + scene + ".fsd";
    const auto p = test::run(pre + " " + file + " -o " + fsd + " --quiet --luminaire-particles 262144");
    ASSERT_EQ(p.exitCode, 0) << p.output;
    std::string image[2];
    for (int off = 0; off < 2; ++off) {
      const std::string out = dir + "/" + scene + (off ? "-off.exr" : "-on.exr");
      const auto r = test::run(render + " " + file + " --firstshot " + fsd + " --integrator irradiance-cache --width 12 " +
                               "--height 9 --spp 1 --ic-samples 32 -q -o " + out + (off ? " --luminaires off" : ""));
      ASSERT_EQ(r.exitCode, 0) << r.output;
      image[off] = test::readFile(out);
    }
    EXPECT_EQ(image[0] != image[1], kept) << scene;
  }
}

// Next-event estimation's choice of an exit patch (LuminaireBoxes::choosePatch) against its probability
// (patchProbability, which MIS weighs by): for receivers around the bowl lamp's box, 2^16 stratified choices per
// receiver, each patch's count within 4σ (binomial) of N·p, the probabilities summing to 1 over the patches chosen,
// and the probability each choice reports equal to patchProbability's.
TEST(LuminaireCache, ExitPatchChoiceMatchesItsProbability) {
  const RenderScene scene = test::withLuminaireTable(test::bowlLamp());
  const LuminaireBoxes& boxes = scene.luminaires();
  ASSERT_FALSE(boxes.empty());
  const Luminaire& lum = boxes.items()[0];
  const Vec3 mid = 0.5f * (lum.lo + lum.hi), size = lum.hi - lum.lo;
  const Vec3 receivers[] = {mid + Vec3(0.0f, 0.6f, 0.0f), mid + Vec3(0.5f, 0.3f, -0.2f), mid + Vec3(-0.9f, -0.4f, 0.3f),
                            mid + Vec3(0.0f, 0.5f * size.y + 0.02f, 0.05f)};
  constexpr int N = 1 << 16;
  for (const Vec3& x : receivers) {
    std::vector<int> count(lum.patchCount(), 0);
    for (int i = 0; i < N; ++i) {
      float u = (float(i) + 0.5f) / float(N), p = 0.0f;
      uint32_t k = 0;
      if (!boxes.choosePatch(0, x, u, k, p)) continue;
      ASSERT_NEAR(p, boxes.patchProbability(0, x, k), 1e-6f * std::max(1.0f, p));
      ++count[k];
    }
    double sum = 0.0;
    for (uint32_t k = 0; k < lum.patchCount(); ++k) {
      const double p = boxes.patchProbability(0, x, k);
      sum += p;
      EXPECT_NEAR(count[k], N * p, 4.0 * std::sqrt(N * p * (1.0 - p)) + 2.0) << "patch " << k;
    }
    EXPECT_NEAR(sum, 1.0, 1e-4);
  }
}
