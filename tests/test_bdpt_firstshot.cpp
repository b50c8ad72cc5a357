// Bidirectional path tracing with a first-shot table (table mode, --bdpt-firstshot patches): the
// small lights' light subpaths start from the patches the table lights. Its path space is the path
// tracer's with the same table (small lights exact at the first non-delta camera vertex, the table
// after it), so the two images agree per 8×8 block within 3σ (σ from the per-pass block means).
#include <gtest/gtest.h>

#include "preprocess/preprocessor.h"
#include "render/integrators/bdpt/integrator.h"
#include "render/light_emission.h"
#include "tests/block_compare.h"
#include "tests/light_tracing_util.h"
#include "tests/test_util.h"

using namespace fs;

namespace {

SceneDesc shipped(const std::string& name) { return loadScene(test::source("scenes/" + name + ".json")); }

/// Table mode, --bdpt-firstshot patches.
IntegratorOptions tableMode() {
  IntegratorOptions io;
  io.bdptFirstShot = true;
  return io;
}

}  // namespace

TEST(BdptFirstShot, CornellAgreesWithPathTracingOnTheSameTable) {
  test::expectAgreesWithPathTracingOnTable("bdpt", "cornell, table", shipped("cornell"), 200, 300, tableMode());
}
TEST(BdptFirstShot, ManyLightsAgreesWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("BdptFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable");
  test::expectAgreesWithPathTracingOnTable("bdpt", "many-lights, table", shipped("many-lights"), 200, 300, tableMode());
}
// Kept (directional) and replaced lights of every kind, over diffuse and glossy patches.
TEST(BdptFirstShot, MixedLightsAgreeWithPathTracingOnTheSameTable) {
  test::expectAgreesWithPathTracingOnTable("bdpt", "mixed-lights, table", test::mixedLightsScene(), 200, 300, tableMode());
}
// Mirrors and glass: x_m lies behind them, and a small light met right after a delta bounce counts.
TEST(BdptFirstShot, MirrorAndGlassAgreeWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("Bdpt.MirrorAndGlassAgreeWithPathTracing and BdptFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable");
  test::expectAgreesWithPathTracingOnTable("bdpt", "mirror-glass, table", test::mirrorGlassScene(), 200, 300, tableMode());
}

// Table mode's emitters: the replaced lights leave, every lit patch side joins with a power of
// albedo·E·A, and a particle's expected power is the total (Σ over particles / N → Σ power).
TEST(BdptFirstShot, EmissionSamplerOverPatchesConservesPower) {
  SceneDesc d = shipped("cornell");
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene scene(d, preprocessScene(d, po));
  FirstShotLighting lighting;
  lighting.build(scene);
  const EmissionSampler emission(scene, lighting);
  for (uint32_t l = 0; l < emission.lightCount(); ++l)
    if (scene.lights().lights()[l].replaced) {
      EXPECT_EQ(emission.power(l), 0.0) << "light " << l;
    }
  ASSERT_GT(emission.totalPower(), 0.0);

  // Monte Carlo estimate of the emitted power against the sum of the emitters' powers: on diffuse
  // patches albedo·E·A is exact, since the table's point-wise E averages to the patch's E.
  test::Moments power;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    Sampler sampler(7, uint64_t(i), 0, 1);
    EmissionSample es;
    double p = 0;
    if (emission.sample(sampler, es)) {
      ASSERT_TRUE(emission.isPatch(es.light));
      ASSERT_GT(es.pdfDir, 0.0f);
      p = (es.power.x + es.power.y + es.power.z) / 3.0;
    }
    power.add(p);
  }
  const double expected = emission.totalPower();
  EXPECT_NEAR(power.mean(), expected, 3.0 * power.se())
      << power.mean() << " ± " << power.se() << " W against Σ albedo·E·A = " << expected << " W";
}

// The option on the command line: both modes render; a value that is not one of them exits 2.
TEST(BdptFirstShot, CommandLine) {
  const std::string dir = test::tempDir(), scene = test::source("scenes/cornell.json"), fsd = dir + "/c.fsd";
  const auto pre = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " " + scene +
                             " --backend embree --resolution 64 --quiet -o " + fsd);
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
  const std::string render = std::string(FIRSTSHOT_RENDER_EXE) + " " + scene + " --firstshot " + fsd +
                             " --integrator bdpt --spp 2 --width 24 --height 20 -q -o " + dir + "/a.exr";
  for (const char* mode : {"patches", "off"}) {
    const auto r = test::run(render + " --bdpt-firstshot " + mode);
    EXPECT_EQ(r.exitCode, 0) << mode << ": " << r.output;
  }
  const auto bad = test::run(render + " --bdpt-firstshot table");
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
}
