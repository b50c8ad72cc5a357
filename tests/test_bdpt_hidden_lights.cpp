// BDPT with a first-shot table (table mode) on the scenes the table is meant for, lights that hide:
// a bulb in an open rough-metal bowl (the room lit from the bowl and the spot it throws on the
// ceiling) and a filament inside a clear glass envelope (no shadow ray passes the glass: every path
// leaves the filament through a delta chain, which no table holds). Table mode must agree with the
// path tracer on the same table (per 8×8 block within 3σ, σ from the per-pass block means), and in the
// glass bulb it must not be noisier than BDPT without the table (σ of the variance from the samples). The
// bowl's glossy lit patches emit by a mixture of the cosine and their BSDF lobe: its density and power.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <vector>

#include "common/sampling/sampling.h"
#include "preprocess/preprocessor.h"
#include "render/firstshot/lighting.h"
#include "render/lights/light_emission.h"
#include "render/loop/renderer.h"
#include "tests/block_compare.h"
#include "tests/hidden_lights_scenes.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;
using firstshot::test::bowlLamp;
using firstshot::test::glassBulb;

namespace {

/// The scene with its first-shot table (Embree item buffers, R = 64, default selection of the small lights).
RenderScene withTable(const SceneDesc& d) {
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  po.luminaires.mode = "off";  // the bulb replaced by the table (found as a luminaire, it would be no replaced light)
  return RenderScene(d, preprocessScene(d, po));
}

IntegratorOptions tableMode(const SceneDesc& d) {
  IntegratorOptions io;
  io.shootFromPatches = true;
  io.maxDepth = d.settings.maxDepth;
  return io;
}

}  // namespace

// The bowl's inside and the ceiling's hot spot come from the lit patches (the bowl's glossy first-shot
// radiance as an emitter); the bulb's direct light at the first camera vertex is exact. The path tracer's
// blocks have a heavy tail here (the hot spot found by BSDF samples): 3000 passes (at 300 one block fell at
// 4.1σ, its σ 10%).
TEST(BdptHiddenLights, BowlLampAgreesWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("BdptHiddenLights.GlassBulbAgreesWithPathTracingOnTheSameTable and GlossyPatchEmissionKeepsThePower");
  const SceneDesc d = bowlLamp();
  const RenderScene scene = withTable(d);
  ASSERT_FALSE(scene.firstShot()->replacedLights.empty());
  test::expectIntegratorsAgree("bowl lamp, table", scene, "bdpt", 200, "path", 3000, tableMode(d));
}

// Every path leaves the filament through the glass: the delta-first light subpaths and the camera
// subpath meeting the filament behind the glass, weighted against each other.
TEST(BdptHiddenLights, GlassBulbAgreesWithPathTracingOnTheSameTable) {
  const SceneDesc d = glassBulb();
  const RenderScene scene = withTable(d);
  ASSERT_FALSE(scene.firstShot()->replacedLights.empty());
  test::expectIntegratorsAgree("glass bulb, table", scene, "bdpt", 200, "path", 1200, tableMode(d));
}

// The table must not make BDPT noisier where no table holds the light: the mean pixel variance with the
// table within 3σ of, or below, the one without (the same sample count; a table mode that lit the room
// only by camera paths meeting the filament was ≈ 20× as noisy).
TEST(BdptHiddenLights, GlassBulbNoNoisierWithTheTable) {
  FIRSTSHOT_STATISTICS_ONLY("BdptHiddenLights.GlassBulbAgreesWithPathTracingOnTheSameTable");
  const SceneDesc d = glassBulb();
  const RenderScene table = withTable(d), plain(d, d.settings.patchSize);
  auto a = makeIntegrator("bdpt", tableMode(d)), b = makeIntegrator("bdpt", tableMode(d));
  a->preprocess(table);
  b->preprocess(plain);
  const test::Moments vt = test::pixelVariance(*a, table, 100), vp = test::pixelVariance(*b, plain, 100);
  fmt::print("glass bulb, mean pixel variance per pass: table {:.4g} ± {:.2g}, without {:.4g} ± {:.2g}\n", vt.mean(),
             vt.se(), vp.mean(), vp.se());
  EXPECT_LT(vt.mean(), vp.mean() + 3.0 * std::hypot(vt.se(), vp.se()));
  EXPECT_LT(vp.se(), 0.2 * vp.mean()) << "too noisy to test";
}

// A glossy lit patch (the bowl, pbr at roughness 0.5) emits in directions drawn from a mixture of the
// cosine and its BSDF lobe about the light centre (EmissionSampler): the particles' density is the one
// pdfDirection() reports, and their mean power is the one of cosine-distributed directions from the same
// points (the same radiant exitance, two estimators; within 3σ, σ from the samples). A density that
// missed the BSDF half (the cosine's alone) makes the mixture's power 3.1× too high.
TEST(BdptHiddenLights, GlossyPatchEmissionKeepsThePower) {
  const SceneDesc d = bowlLamp();
  const RenderScene scene = withTable(d);
  FirstShotLighting lighting;
  lighting.build(scene);
  const EmissionSampler emission(scene, lighting);
  test::Moments mixture, cosine;
  int glossy = 0;
  for (int i = 0; i < 200000; ++i) {
    Sampler sampler(11, uint64_t(i), 0, 1);
    EmissionSample es;
    double pm = 0, pc = 0;
    if (emission.sample(sampler, es)) {
      ASSERT_TRUE(emission.isPatch(es.light));
      const float pdf = emission.pdfDirection(es.light, es.p, es.n, es.d);
      ASSERT_NEAR(es.pdfDir, pdf, 1e-4f * pdf) << "particle " << i;
      pm = (es.power.x + es.power.y + es.power.z) / 3.0;
      glossy += scene.patchBsdf(emission.patchOf(es.light)).isDiffuse() ? 0 : 1;
    }
    // The same point (the emitter and point are drawn first), a cosine direction of its own.
    Sampler again(11, uint64_t(i), 0, 1);
    const double u = again.next1Dd();
    const Vec2 uPos = again.next2D(), uDir = Vec2(sampler.next1D(), sampler.next1D());
    EmissionSample o;
    if (emission.sampleOrigin(u, uPos, o)) {
      const Vec3 local = squareToCosineHemisphere(uDir);
      const Color L = emission.patchRadiance(o.light, o.p, Frame(o.n).toWorld(local));
      const Color phi = L * (local.z / (o.pdfLight * o.pdfPos * squareToCosineHemispherePdf(local)));
      pc = (phi.x + phi.y + phi.z) / 3.0;
    }
    mixture.add(pm), cosine.add(pc);
  }
  fmt::print("glossy particles {} of 200000; mean power: mixture {:.5g} ± {:.2g} W, cosine {:.5g} ± {:.2g} W\n", glossy,
             mixture.mean(), mixture.se(), cosine.mean(), cosine.se());
  EXPECT_GT(glossy, 20000);
  EXPECT_LT(std::abs(mixture.mean() - cosine.mean()), 3.0 * std::hypot(mixture.se(), cosine.se()));
}
