// The shooting integrators with a first-shot table (table mode, --shoot-firstshot patches): light
// tracing's particles and BDPT's light subpaths leave the lit patches instead of the small lights,
// and the small lights' direct light at the first non-delta camera vertex is taken exactly. Their
// path space is the path tracer's with the same table (small lights exact at that vertex, the
// table after it), so the images agree per 8×8 block within 3σ (σ from the per-pass block means).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/bdpt/integrator.h"
#include "render/lights/light_emission.h"
#include "tests/block_compare.h"
#include "tests/light_tracing_util.h"
#include "tests/splat_checks.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

SceneDesc shipped(const std::string& name) { return loadScene(test::source("scenes/" + name + ".json")); }

/// A shooting integrator and its passes against the path tracer's on a scene of 12 blocks.
struct Shooter {
  std::string integrator;
  int passes;    ///< the shooting integrator's passes (the path tracer: 300)
  int heavyTail; ///< the factor on both where its blocks' means have a heavy tail (many-lights)
};

class ShootingFirstShot : public testing::TestWithParam<Shooter> {
 protected:
  /// Table mode against path tracing on the same table; @p scale multiplies both pass counts.
  static void expectAgrees(const std::string& name, SceneDesc d, int scale = 1) {
    IntegratorOptions io;
    io.shootFromPatches = true;
    test::expectAgreesWithPathTracingOnTable(GetParam().integrator, name, std::move(d), GetParam().passes * scale,
                                             300 * scale, io);
  }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Integrators, ShootingFirstShot,
                         testing::Values(Shooter{"light", 300, 4}, Shooter{"bdpt", 200, 1}),
                         [](const testing::TestParamInfo<Shooter>& p) { return p.param.integrator; });

TEST_P(ShootingFirstShot, CornellAgreesWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("Integrators/ShootingFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable");
  expectAgrees("cornell, table", shipped("cornell"));
}
// Two bounces: a path from a lit patch has one bounce more than its vertices show (the table's),
// as the path tracer counts a lit patch met at depth d as d + 1 (light 31σ, bdpt 35σ off without
// it). 4× the passes: at 200 and 300 one bdpt block of 12 fell at 3.1σ by chance (2.7σ at 4×).
TEST_P(ShootingFirstShot, CornellAtTwoBouncesAgreesWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("Integrators/ShootingFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable");
  SceneDesc d = shipped("cornell");
  d.settings.maxDepth = 2;
  expectAgrees("cornell, 2 bounces, table", d, 4);
}
TEST_P(ShootingFirstShot, ManyLightsAgreesWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("ShootingFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable");
  expectAgrees("many-lights, table", shipped("many-lights"), GetParam().heavyTail);
}
// Table mode's particles and its per-pixel part: the same film for 1 and 2 threads and pass by pass.
TEST_P(ShootingFirstShot, BitIdenticalForOneAndTwoThreadsAndByPasses) {
  test::expectSameFilmForThreadsAndPasses(GetParam().integrator, true);
}
// Kept (directional) and replaced lights of every kind, over diffuse and glossy patches.
TEST_P(ShootingFirstShot, MixedLightsAgreeWithPathTracingOnTheSameTable) {
  expectAgrees("mixed-lights, table", test::mixedLightsScene());
}
// Mirrors and glass: x_m lies behind them (bdpt; light tracing takes the path tracer's estimate
// there), and a small area light's light reflected by them first counts (light tracing: the
// delta-first particles, 5.6σ off without them).
TEST_P(ShootingFirstShot, MirrorAndGlassAgreeWithPathTracingOnTheSameTable) {
  FIRSTSHOT_STATISTICS_ONLY("ShootingFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable");
  expectAgrees("mirror-glass, table", test::mirrorGlassScene());
}

/// Table mode's emitters on cornell's table (Embree item buffers, R = 64).
class ShootingFirstShotEmission : public testing::Test {
 protected:
  static PreprocessOptions options(const SceneDesc& d) {
    PreprocessOptions po = defaultOptions(d);
    po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
    return po;
  }
  SceneDesc d = shipped("cornell");
  const RenderScene scene{d, preprocessScene(d, options(d))};
  const FirstShotLighting lighting = [this] {
    FirstShotLighting l;
    l.build(scene);
    return l;
  }();
  const EmissionSampler emission{scene, lighting};
};

// Table mode's emitters: the replaced lights leave, every lit patch side joins with a power of
// albedo·E·A, and a particle's expected power is the total (Σ over particles / N → Σ power).
TEST_F(ShootingFirstShotEmission, OverPatchesConservesPower) {
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

// The option on the command line, for both integrators: both modes render; a value that is not
// one of them exits 2.
// The guide table (common/sampling/distribution_1d.h) only narrows the search: every u picks the emitter
// that inverting the whole power CDF picks, on the cornell table's 4 k patch sides, the bucket edges
// included (u = b/n and its neighbouring doubles), where a guide one bucket off would show.
TEST_F(ShootingFirstShotEmission, GuidedChoiceInvertsThePowerCdf) {
  const size_t n = emission.lightCount() + emission.patchSideCount();
  ASSERT_GT(n, 1000u);
  std::vector<double> cdf;  // finish()'s arithmetic
  double sum = 0;
  for (size_t e = 0; e < n; ++e) cdf.push_back((sum += emission.power(e)) / emission.totalPower());
  cdf.back() = 1.0;
  std::vector<double> us;
  for (size_t b = 0; b <= n; ++b) {
    const double edge = double(b) / double(n);
    us.insert(us.end(), {edge, std::nextafter(edge, 0.0), std::nextafter(edge, 1.0)});
  }
  for (size_t e = 0; e < n; ++e) us.insert(us.end(), {cdf[e], std::nextafter(cdf[e], 0.0)});
  Sampler random(3, 0, 0, 0);
  for (int i = 0; i < 100000; ++i) us.push_back(random.next1Dd());
  size_t checked = 0;
  for (double u : us) {
    u = std::clamp(u, 0.0, 1.0);
    const size_t expected = std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()), n - 1);
    if (!(emission.power(expected) > 0)) continue;  // sampleOrigin() refuses an emitter without power
    EmissionSample es;
    ASSERT_TRUE(emission.sampleOrigin(u, Vec2(0.5f), es)) << u;
    ASSERT_EQ(es.light, expected) << "u = " << u;
    ++checked;
  }
  EXPECT_GT(checked, us.size() / 2);
}

TEST(ShootingFirstShotCli, CommandLine) {
  const std::string dir = test::tempDir(), scene = test::source("scenes/cornell.json"), fsd = dir + "/c.fsd";
  const auto pre = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " " + scene +
                             " --backend embree --resolution 64 --quiet -o " + fsd);
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
  for (const char* integrator : {"light", "bdpt"}) {
    const std::string render = std::string(FIRSTSHOT_RENDER_EXE) + " " + scene + " --firstshot " + fsd +
                               " --integrator " + integrator + " --spp 2 --width 24 --height 20 -q -o " + dir + "/a.exr";
    for (const char* mode : {"patches", "off"}) {
      const auto r = test::run(render + " --shoot-firstshot " + mode);
      EXPECT_EQ(r.exitCode, 0) << integrator << " " << mode << ": " << r.output;
    }
    const auto bad = test::run(render + " --shoot-firstshot table");
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
  }
}
