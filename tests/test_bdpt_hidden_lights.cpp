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

#include "common/sampling.h"
#include "preprocess/preprocessor.h"
#include "render/firstshot/lighting.h"
#include "render/lights/light_emission.h"
#include "render/loop/renderer.h"
#include "tests/block_compare.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace fs;

namespace {

/// A 2 m × 1.5 m × 2 m room with a table (32×24, max depth 6); @p materials and @p shapes add the lamp's (JSON members).
SceneDesc room(const std::string& materials, const std::string& shapes) {
  return test::sceneFromJson(R"({"materials": {"wall": {"type": "diffuse", "albedo": 0.7},
      "floor": {"type": "diffuse", "albedo": [0.5, 0.4, 0.3]}, "table": {"type": "diffuse", "albedo": [0.6, 0.6, 0.55]}, )" +
                             materials + R"(},
    "shapes": [{"type": "box", "material": "wall", "min": [0,0,0], "max": [2,1.5,2], "flip_normals": true},
               {"type": "quad", "material": "floor", "vertices": [[0,0.001,0],[0,0.001,2],[2,0.001,2],[2,0.001,0]]},
               {"type": "box", "material": "table", "min": [0.2,0,1.1], "max": [0.9,0.5,1.7]}, )" +
                             shapes + R"(],
    "camera": {"position": [1.9, 0.9, 1.9], "look_at": [0.6, 0.6, 0.5], "fov_y": 70, "resolution": [32, 24]},
    "settings": {"patch_size": 0.4, "max_depth": 6}})");
}

/// A bulb (r = 3 cm) in an open metal bowl (pbr, roughness 0.5, 24 cm × 24 cm × 10 cm) at 0.9 m.
SceneDesc bowlLamp() {
  return room(R"("bowl": {"type": "pbr", "base_color": [0.8, 0.75, 0.7], "metallic": 1, "roughness": 0.5},
                 "bulb": {"type": "diffuse", "emission": 60})",
              R"({"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,0.88],[1.52,0.9,0.88],[1.52,0.9,1.12],[1.28,0.9,1.12]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,0.88],[1.28,0.9,1.12],[1.28,1.0,1.12],[1.28,1.0,0.88]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.52,0.9,0.88],[1.52,1.0,0.88],[1.52,1.0,1.12],[1.52,0.9,1.12]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,0.88],[1.28,1.0,0.88],[1.52,1.0,0.88],[1.52,0.9,0.88]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,1.12],[1.52,0.9,1.12],[1.52,1.0,1.12],[1.28,1.0,1.12]]},
                 {"type": "sphere", "material": "bulb", "center": [1.4, 0.94, 1.0], "radius": 0.03, "subdivisions": 2})");
}

/// A filament (r = 8 cm, so that the path tracer's BSDF samples find it) inside a clear glass envelope (r = 20 cm,
/// ior 1.5) hanging at 1.1 m.
SceneDesc glassBulb() {
  return room(R"("glass": {"type": "dielectric", "ior": 1.5}, "filament": {"type": "diffuse", "emission": 12})",
              R"({"type": "sphere", "material": "glass", "center": [1.2, 1.1, 1.0], "radius": 0.2, "subdivisions": 3, "smooth": true},
                 {"type": "sphere", "material": "filament", "center": [1.2, 1.1, 1.0], "radius": 0.08, "subdivisions": 2})");
}

/// The scene with its first-shot table (Embree item buffers, R = 64, default selection of the small lights).
RenderScene withTable(const SceneDesc& d) {
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  return RenderScene(d, preprocessScene(d, po));
}

/// Per-pixel noise of @p integrator: passes 2k and 2k + 1 (one sample per pixel each) give
/// d_k = mean over pixels of (x_2k − x_2k+1)²/2, an unbiased estimate of the mean pixel variance of one
/// pass; the d_k of different k are independent, so their mean has a σ from the samples.
test::Moments pixelVariance(const Integrator& integrator, const RenderScene& scene, int pairs) {
  const Camera camera(scene.desc().camera);
  const int w = camera.width(), h = camera.height();
  auto pass = [&](int k) {
    Film film(w, h);
    RenderOptions ro;
    ro.spp = 1, ro.firstSample = k, ro.seed = 7;
    render(integrator, camera, film, ro);
    std::vector<double> v(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Vec3d m = film.mean(x, y);
        v[size_t(y) * w + x] = (m.x + m.y + m.z) / 3.0;
      }
    return v;
  };
  test::Moments d;
  for (int k = 0; k < pairs; ++k) {
    const std::vector<double> a = pass(2 * k), b = pass(2 * k + 1);
    double sum = 0;
    for (size_t p = 0; p < a.size(); ++p) sum += (a[p] - b[p]) * (a[p] - b[p]) / 2.0;
    d.add(sum / double(a.size()));
  }
  return d;
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
  const SceneDesc d = glassBulb();
  const RenderScene table = withTable(d), plain(d, d.settings.patchSize);
  auto a = makeIntegrator("bdpt", tableMode(d)), b = makeIntegrator("bdpt", tableMode(d));
  a->preprocess(table);
  b->preprocess(plain);
  const test::Moments vt = pixelVariance(*a, table, 100), vp = pixelVariance(*b, plain, 100);
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
