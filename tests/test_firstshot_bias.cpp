// Bias of first-shot at default settings (R = 256, analytic estimator, GL item buffers): image
// means against NEE path tracing of the same path length (camera samples that see the light left
// out), every patch of a closed room against its exact factor (edges, corners, grazing patches),
// and patches half buried under a box (their exposed points must get the exposed part's light).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/sampling/sampling.h"
#include "tests/bias_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// Number of outline edges of its own shape's faces that patch @p p touches (0 interior, 1 along
/// an edge, 2 or more in a corner).
int borderEdges(const SceneDesc& desc, const Patch& p) {
  const ShapeDesc& s = desc.shapes[p.shape];
  int edges = 0;
  std::vector<std::pair<uint32_t, uint32_t>> seen;  // a segment shared by two faces counts once
  for (const Face& f : s.faces)
    for (int e = 0; e < f.count; ++e) {
      const uint32_t i0 = std::min(f.v[e], f.v[(e + 1) % f.count]), i1 = std::max(f.v[e], f.v[(e + 1) % f.count]);
      if (std::find(seen.begin(), seen.end(), std::make_pair(i0, i1)) != seen.end()) continue;
      seen.emplace_back(i0, i1);
      const Vec3d a = s.vertices[f.v[e]], b = s.vertices[f.v[(e + 1) % f.count]];
      const double len = glm::length(b - a);
      bool on = false;
      for (uint32_t k = 0; k < p.count && !on; ++k) {
        const Vec3d q(p.v[k]);
        const double t = glm::dot(q - a, b - a) / (len * len);
        on = t >= -1e-6 && t <= 1 + 1e-6 && glm::length(a + t * (b - a) - q) < 1e-5 * len;
      }
      edges += on;
    }
  return edges;
}

SceneDesc named(const std::string& name) {
  // A shipped scene's name, or the path of any scene file (a name with a '/').
  SceneDesc d = name == "cornell-metre"                  ? test::cornellMetre()
                : name.find('/') != std::string::npos ? loadScene(name)
                                                       : loadScene(test::source("scenes/" + name + ".json"));
  d.camera.width = d.camera.height = 64;
  if (std::getenv("FSBIAS_LPS")) d.settings.lightPatchSize = std::atof(std::getenv("FSBIAS_LPS"));
  if (std::getenv("FSBIAS_PS")) d.settings.patchSize = std::atof(std::getenv("FSBIAS_PS"));
  if (std::getenv("FSBIAS_MPS")) d.settings.minPatchSize = std::atof(std::getenv("FSBIAS_MPS"));
  if (std::getenv("FSBIAS_TOL")) d.settings.refineTolerance = std::atof(std::getenv("FSBIAS_TOL"));
  if (std::getenv("FSBIAS_LTOL")) d.settings.lightTolerance = std::atof(std::getenv("FSBIAS_LTOL"));
  return d;
}


/// Paired first-shot − NEE image mean of @p desc (max depth 3) at default preprocess settings.
test::BiasMeasure imageBias(const SceneDesc& desc, int spp) {
  return test::firstShotImageBias(desc, test::preprocessDefault(desc), spp);
}

/// The target: the image mean within 0.3% of NEE at 3σ, |bias| + 3σ < 0.3%. (Not "no bias within
/// 3σ": the exact estimators leave a known bias of ~0.01% that enough samples resolve, e.g. many-lights
/// −0.010% ± 0.001% at 64×64 × 16 spp, far inside the target.)
void expectUnbiased(const std::string& what, const test::BiasMeasure& m) {
  fmt::print("{}: first-shot − NEE = {:+.3f}% ± {:.3f}% of the image mean\n", what, 100 * m.relative(), 100 * m.relativeSe());
  EXPECT_GT(m.se, 0.0);
  EXPECT_LT(std::abs(m.relative()) + 3 * m.relativeSe(), 0.003) << what;
  EXPECT_LT(m.relativeSe(), 0.001) << what << ": too noisy to tell 0.3%";
}

}  // namespace

// Was −0.29% ± 0.04% (patch-averaged irradiance on the floor around the blocks, whose buried part
// counted as shadow), now ≈ −0.06% ± 0.04%.
TEST(FirstShotBias, CornellImageMeanAgreesWithNee) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 48;
  expectUnbiased("cornell", imageBias(desc, 96));
}

// The box at 5.56 m, light 1 cm under the ceiling. Was −0.32% ± 0.04%.
TEST(FirstShotBias, MetreCornellImageMeanAgreesWithNee) {
  SceneDesc desc = test::cornellMetre();
  desc.camera.width = desc.camera.height = 48;
  expectUnbiased("cornell ×10", imageBias(desc, 96));
}

// The same box with the scene's own 0.025 m patches (457,188 of them, most narrower than a pixel
// seen from the light, occluders included). Was −0.95% ± 0.07%.
TEST(FirstShotBias, MetreCornellFinePatchesImageMeanAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("FirstShotBias.MetreCornellImageMeanAgreesWithNee");
  SceneDesc desc = test::cornellMetre();
  desc.settings.patchSize = desc.settings.minPatchSize = 0.025;  // uniform
  desc.camera.width = desc.camera.height = 48;
  expectUnbiased("cornell ×10, 0.025 m patches", imageBias(desc, 64));
}

// Where a surface stands on a half-shadowed one, a patch-constant visible fraction lights the
// contact from the patch's lit part. A close-up of the bottom of cornell's short block (its front
// face in the shade, the floor before it in the block's penumbra) at default settings, max depth 3.
// Refinement down to min_patch_size = patch_size/8 (the old default) gave +1.48% ± 0.09%, /16 (the
// default) +0.47% ± 0.08%, /32 +0.18% ± 0.08%; the bound fails for /8.
TEST(FirstShotBias, ContactWithAPenumbraAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("FirstShotBias.CornellImageMeanAgreesWithNee");
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  const Vec3d bottom(0.21, 0.02, 0.0895), facing(0.2928, 0.0, -0.9562);  // the face's middle, 2 cm up; its normal
  desc.camera.position = bottom + 0.25 * facing + Vec3d(0, 0.03, 0);
  desc.camera.lookAt = bottom;
  desc.camera.fovYDeg = 30;
  desc.camera.width = desc.camera.height = 32;
  const test::BiasMeasure m = imageBias(desc, 512);
  fmt::print("contact: first-shot − NEE = {:+.3f}% ± {:.3f}%\n", 100 * m.relative(), 100 * m.relativeSe());
  EXPECT_LT(std::abs(m.relative()) + 3 * m.relativeSe(), 0.01);
}

// A 30 cm sphere lamp 20 cm over a table, the floor under it in the table's wide penumbra: the
// lamp is twelve isotropic samples on a shell inside it (preprocess/sphere_light.h), whose soft
// shadow is the mean of twelve sharp ones. One sample at the centre gave +0.19% ± 0.06%, the sphere's
// 203 surface samples +0.12% ± 0.06% (at 64 × 64 × 1024 spp). An area light's point samples must not
// say where the light is seen for NEE (render/firstshot/table_visibility.h): they did, +3.8%.
TEST(FirstShotBias, SphereLampOverATableAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("SphereLight.ANearSphereIsTwelveSamplesOnAShellThatLightTheRoomAsItsTriangles");
  SceneDesc desc = test::sceneFromJson(R"({"materials": {"wall": {"type": "diffuse", "albedo": 0.7},
      "wood": {"type": "diffuse", "albedo": [0.5, 0.4, 0.3]}, "bulb": {"type": "diffuse", "emission": 150}},
    "shapes": [{"type": "box", "material": "wall", "min": [0, 0, 0], "max": [4, 3, 4], "flip_normals": true},
               {"type": "box", "material": "wood", "min": [1.2, 0.7, 1.4], "max": [2.4, 0.75, 2.2]},
               {"type": "box", "material": "wood", "min": [1.25, 0, 1.45], "max": [1.3, 0.7, 1.5]},
               {"type": "sphere", "material": "bulb", "center": [1.8, 1.1, 1.8], "radius": 0.15, "subdivisions": 4}],
    "camera": {"position": [0.3, 0.5, 3.7], "look_at": [1.8, 0.2, 1.8], "fov_y": 60, "resolution": [48, 48]}})");
  const FirstShotTable table = test::preprocessDefault(desc);
  ASSERT_EQ(table.samples.size(), 12u);
  expectUnbiased("sphere lamp over a table", test::firstShotImageBias(desc, table, 2048));
}

// 64 point lights 0.2 m under the ceiling: the far ceiling is seen edge-on from every light. Was
// −0.49% ± 0.03% (grazing patches narrower than a pixel got nothing), now 0.000% ± 0.001%.
TEST(FirstShotBias, ManyLightsImageMeanAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("FirstShotBias.CornellImageMeanAgreesWithNee");
  SceneDesc desc = loadScene(test::source("scenes/many-lights.json"));
  desc.camera.width = 40, desc.camera.height = 30;
  expectUnbiased("many-lights", imageBias(desc, 8));
}

// The shipped scenes as a user's scene would come, with no patch size: the automatic size (common/patches/patch_size.h)
// and its refinement keep the image within 0.3% of NEE (measured at 64×64 × 128 spp: cornell −0.077% ± 0.029%,
// many-lights −0.009% ± 0.001%, sierpinski-glossy −0.039% ± 0.002%, fixture-room −0.046% ± 0.009%, office-floor
// −0.015% ± 0.013%; FSBIAS_PS=0 FSBIAS_MPS=0 with FirstShotBias.DISABLED_Measure).
TEST(FirstShotBias, AutomaticPatchSizeAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("AutomaticPatchSize.BoundsTheCoarseCountAndScalesWithTheScene");
  for (const char* name : {"cornell", "fixture-room"}) {
    SceneDesc desc = loadScene(test::source(std::string("scenes/") + name + ".json"));
    desc.settings.patchSize = desc.settings.minPatchSize = 0;
    desc.camera.width = desc.camera.height = 48;
    expectUnbiased(std::string(name) + ", automatic patch size", imageBias(desc, 128));
  }
}

// A point light near the ceiling of a closed, convex room of 5 cm patches: nothing occludes, so
// every patch's factor must be its exact Ω_j/(4π A_j), those along the shared edges and in the
// corners (where neighbouring walls compete for pixels) and those seen edge-on (narrower than a
// pixel) included, and the room must receive the whole flux.
TEST(FirstShotBias, ClosedRoomEdgesAndCornersGetTheirExactFactor) {
  const SceneDesc desc = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [3,2,2.5], "flip_normals": true}],
    "lights": [{"type": "point", "position": [0.71, 1.93, 0.87], "power": 10}],
    "settings": {"patch_size": 0.05}})");
  const FirstShotTable t = test::preprocessDefault(desc);
  const Vec3d L = desc.lights[0].position, hi(3, 2, 2.5);
  double worst[3] = {0, 0, 0}, flux = 0;
  int count[3] = {0, 0, 0};
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const Patch& p = t.mesh.patches[j];
    std::vector<Vec3d> poly;
    for (uint32_t k = 0; k < p.count; ++k) poly.emplace_back(p.v[k]);
    const double exact = analytic::solidAnglePolygon(L, poly) / (4 * kPi * p.area);
    const double got = t.rowStart[j + 1] > t.rowStart[j] ? t.factor[t.rowStart[j]] : 0.0;
    flux += got * p.area;
    int planes = 0;  // room planes (other than the patch's own) that the patch touches
    for (int axis = 0; axis < 3; ++axis)
      for (double wall : {0.0, hi[axis]}) {
        bool touches = false, on = true;
        for (uint32_t k = 0; k < p.count; ++k) {
          const bool at = std::abs(p.v[k][axis] - wall) < 1e-6;
          touches = touches || at, on = on && at;
        }
        planes += touches && !on;
      }
    const int c = std::min(2, planes);
    worst[c] = std::max(worst[c], std::abs(got / exact - 1));
    ++count[c];
  }
  const char* names[3] = {"interior", "edge", "corner"};
  for (int c = 0; c < 3; ++c) {
    fmt::print("  {} patches ({}): largest relative error {:.2e}\n", names[c], count[c], worst[c]);
    EXPECT_GT(count[c], 0);
    EXPECT_LT(worst[c], 1e-5) << names[c];
  }
  fmt::print("  flux received: {:.6f}\n", flux);
  EXPECT_NEAR(flux, 1.0, 1e-5);
}

// A flat box (0.5 mm, so that its shadow, 0.15 mm wide, does not count) standing on a floor of 0.2 m
// patches, its sides through the middle of patches. On the floor patches it half covers, the
// first-shot irradiance at exposed points (what a path can hit) must be the exact one there: the
// visible fraction is taken over the exposed part, not the buried part under the box (which counted
// as shadow and halved those patches). For a point light and for a spot (whose factors were pixel
// sums over the whole patch until the spot got the analytic estimator: −14% on such patches, and
// −0.38% over the office floor's image).
TEST(FirstShotBias, PatchesHalfUnderABoxGetTheirExposedPartsLight) {
  for (const char* light : {R"({"type": "point", "position": [0.02, 1.0, 0.03], "power": 10})",
                            R"({"type": "spot", "position": [0.02, 1.0, 0.03], "direction": [0, -1, 0], "power": 10,
                                "inner_angle": 30, "outer_angle": 70})"}) {
    SCOPED_TRACE(light);
    const SceneDesc desc = test::sceneFromJson(std::string(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
      "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
                 {"type": "box", "material": "white", "min": [-0.3,0,-0.3], "max": [0.3,0.0005,0.3]}],
      "lights": [)") + light + R"(], "settings": {"patch_size": 0.2}})");
    const RenderScene scene(desc, test::preprocessDefault(desc));
    const FirstShotTable& t = *scene.firstShot();
    FirstShotLighting fsl;  // the renderer's first-shot term: recovered V_ij × the exact kernel at x
    fsl.build(scene);
    auto exposed = [](const Vec3& x) { return std::abs(x.x) > 0.3f || std::abs(x.z) > 0.3f; };
    double sumRel = 0, worst = 0;
    int straddling = 0;
    for (uint32_t j = 0; j < t.mesh.size(); ++j) {
      const Patch& p = t.mesh.patches[j];
      if (p.shape != 0) continue;
      int in = 0, out = 0;
      for (uint32_t k = 0; k < p.count; ++k) (exposed(p.v[k]) ? out : in)++;
      if (in == 0 || out == 0 || std::abs(p.centroid.x) > 0.4f || std::abs(p.centroid.z) > 0.4f) continue;
      const LightSample& ls = t.samples[0];
      double table = 0, exact = 0;
      int n = 0;
      for (int m = 0; m < 4000; ++m) {
        Sampler sm(17, j, m);
        const Vec3 x = test::samplePatch(p, sm.next2D());
        if (!exposed(x)) continue;
        ++n;
        Hit h;
        h.p = x, h.ng = p.normal, h.patch = j;
        table += fsl.irradiance(h, true).x;
        const Vec3 o = x + p.normal * 1e-5f, d = ls.position - o;
        if (!scene.occluded(Ray(o, glm::normalize(d), 0.0f, glm::length(d) * (1 - 1e-5f))))
          exact += test::unoccludedSampleIrradiance(ls, x, p.normal, &desc.lights[0]).x;
      }
      const double rel = table / exact - 1;
      fmt::print("  patch at ({:+.1f}, {:+.1f}): {:.0f}% exposed, exposed-point irradiance {:+.2f}% off\n", p.centroid.x,
                 p.centroid.z, 100.0 * n / 4000, 100 * rel);
      sumRel += rel, worst = std::max(worst, std::abs(rel)), ++straddling;
    }
    ASSERT_EQ(straddling, 12);
    EXPECT_LT(worst, 0.01);
    EXPECT_LT(std::abs(sumRel / straddling), 0.005);
  }
}

// A spot 0.8 m over a floor of 0.2 m patches: its irradiance changes a lot across a patch (1/d², and
// the profile's edge between 20° and 40°). The first-shot term at points of the floor must follow
// it, as it does for point lights (was: the patch average, 21% rel. L2 error, 38% of the peak at worst).
TEST(FirstShotBias, SpotIrradianceIsEvaluatedPerPoint) {
  const SceneDesc desc = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-1.5,0,-1.5],[-1.5,0,1.5],[1.5,0,1.5],[1.5,0,-1.5]]}],
    "lights": [{"type": "spot", "position": [0.05, 0.8, 0.02], "direction": [0, -1, 0], "power": 10,
                "inner_angle": 20, "outer_angle": 40}],
    "settings": {"patch_size": 0.2}})");
  const RenderScene scene(desc, test::preprocessDefault(desc));
  FirstShotLighting fsl;
  fsl.build(scene);
  const LightSample& ls = scene.firstShot()->samples[0];
  double err2 = 0, ref2 = 0, worst = 0, peak = 0;
  for (int m = 0; m < 20000; ++m) {
    Sampler sm(23, 0, m);
    const Vec2 u = sm.next2D();
    const Vec3 top(-1.2f + 2.4f * u.x, 1.0f, -1.2f + 2.4f * u.y);
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray(top, Vec3(0, -1, 0)), hit));
    const double exact = test::unoccludedSampleIrradiance(ls, hit.p, Vec3(0, 1, 0), &desc.lights[0]).x;
    const double got = fsl.irradiance(hit, hit.ng.y > 0.0f).x;
    err2 += (got - exact) * (got - exact), ref2 += exact * exact;
    worst = std::max(worst, std::abs(got - exact)), peak = std::max(peak, exact);
  }
  const double rel = std::sqrt(err2 / ref2);
  fmt::print("  spot over a floor: per-point first-shot irradiance rel. L2 error {:.2e}, worst {:.2e} of the peak\n", rel,
             worst / peak);
  EXPECT_LT(rel, 0.01);
  EXPECT_LT(worst / peak, 0.03);
}

/// Measurement harness, not a check (disabled; run with --gtest_also_run_disabled_tests). Per scene:
/// preprocess time, the paired first-shot − NEE image mean, flux per light sample, and each patch's
/// table irradiance against brute-force Monte Carlo by border class. Environment:
///   FSBIAS_SCENES  comma-separated: cornell, cornell-metre, many-lights, ... (default all three)
///   FSBIAS_BACKEND gl | embree;  FSBIAS_SPP camera samples per pixel (256);  FSBIAS_MC points per patch (64)
///   FSBIAS_DEPTH   max depth (3);  FSBIAS_PS / FSBIAS_MPS / FSBIAS_LPS patch / smallest patch / light patch size, m
///   FSBIAS_TOL     refinement tolerance;  FSBIAS_LTOL light tolerance
///   FSBIAS_TIME    also time first-shot and NEE renders;  FSBIAS_MAP print 8×8 blocks of the difference
///   FSBIAS_POINT   per-point first-shot − exact irradiance by shape (FSBIAS_EXPOSED: points inside closed objects left out);  FSBIAS_WORST=N per-shape sums and the N worst patches
TEST(FirstShotBias, DISABLED_Measure) {
  const char* env = std::getenv("FSBIAS_SCENES");
  const std::string list = env ? env : "cornell,cornell-metre,many-lights";
  const std::string backend = std::getenv("FSBIAS_BACKEND") ? std::getenv("FSBIAS_BACKEND") : "gl";
  const int spp = std::getenv("FSBIAS_SPP") ? std::atoi(std::getenv("FSBIAS_SPP")) : 256;
  const int mcPoints = std::getenv("FSBIAS_MC") ? std::atoi(std::getenv("FSBIAS_MC")) : 64;
  size_t start = 0;
  while (start < list.size()) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    start = comma + 1;
    const SceneDesc desc = named(name);
    const auto t0 = std::chrono::steady_clock::now();
    FirstShotTable table = test::preprocessDefault(desc, backend);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const RenderScene nee(desc, table.mesh.patchSize), fsScene(desc, std::move(table));
    IntegratorOptions io;
    io.maxDepth = std::getenv("FSBIAS_DEPTH") ? std::atoi(std::getenv("FSBIAS_DEPTH")) : 3;
    io.lightSampler = LightStrategy::All;  // pairing: both integrators draw the same random numbers
    auto a = makeIntegrator("path", io), b = makeIntegrator("path", io);
    a->preprocess(fsScene);
    b->preprocess(nee);
    const Camera camera(desc.camera);
    const auto m = test::measurePairedBias(*a, *b, nee, camera, spp, 11);
    fmt::print("{} ({}): preprocess {:.2f} s, {} patches, {} samples, {} factors; image {:+.3f}% ± {:.3f}% (NEE mean {:.5f})\n",
               name, backend, secs, fsScene.mesh().size(), fsScene.firstShot()->samples.size(),
               fsScene.firstShot()->nonZeros(), 100 * m.relative(), 100 * m.relativeSe(), m.reference);
    if (std::getenv("FSBIAS_TIME")) {  // render time, first-shot against NEE, same spp
      for (int k = 0; k < 2; ++k) {
        const auto r0 = std::chrono::steady_clock::now();
        test::renderPath(k ? nee : fsScene, io, spp, 3);
        fmt::print("  render {} spp {}: {:.3f} s\n", spp, k ? "NEE" : "first-shot",
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count());
      }
    }
    // Per patch: table (front side) against Monte Carlo, power-weighted, by border class.
    const FirstShotTable& t = *fsScene.firstShot();
    const std::vector<Color> side = t.sideIrradiance();
    const uint32_t n = t.mesh.size();
    std::vector<double> mc(n), mcSe(n);
    tbb::parallel_for(0u, n, [&](uint32_t j) { test::patchIrradianceMC(fsScene, j, mcPoints, 5, mc[j], mcSe[j]); });
    if (std::getenv("FSBIAS_POINT")) {  // per-point first-shot minus exact, uniform points, by shape
      FirstShotLighting fsl;
      fsl.build(fsScene);
      std::vector<double> dm(n), ds(n);
      const bool exposed = std::getenv("FSBIAS_EXPOSED") != nullptr;
      tbb::parallel_for(0u, n, [&](uint32_t j) { test::patchIrradianceMC(fsScene, j, mcPoints, 6, dm[j], ds[j], &fsl, exposed); });
      std::vector<double> d(desc.shapes.size()), v(desc.shapes.size());
      double total = 0, all = 0, allVar = 0;
      for (uint32_t j = 0; j < n; ++j) {
        const Patch& p = t.mesh.patches[j];
        d[p.shape] += p.area * dm[j], v[p.shape] += p.area * p.area * ds[j] * ds[j], total += p.area * mc[j];
        all += p.area * dm[j], allVar += p.area * p.area * ds[j] * ds[j];
      }
      if (d.size() <= 32 || std::getenv("FSBIAS_SHAPES"))
        for (size_t k = 0; k < d.size(); ++k)
          fmt::print("  per point, shape {:2} {:20}: first-shot - exact = {:+.4f}% ± {:.4f}% of all power\n", k,
                     desc.shapes[k].name, 100 * d[k] / total, 100 * std::sqrt(v[k]) / total);
      if (std::getenv("FSBIAS_WORSTPOINT")) {  // the patches that lose most, with their table entries
        std::vector<uint32_t> order(n);
        for (uint32_t j = 0; j < n; ++j) order[j] = j;
        std::sort(order.begin(), order.end(), [&](uint32_t ja, uint32_t jb) {
          return t.mesh.patches[ja].area * dm[ja] < t.mesh.patches[jb].area * dm[jb];
        });
        for (int k = 0; k < std::atoi(std::getenv("FSBIAS_WORSTPOINT")); ++k) {
          const uint32_t j = order[size_t(k)];
          const Patch& p = t.mesh.patches[j];
          for (uint64_t f = t.rowStart[j]; f < t.rowStart[j + 1]; ++f) {  // each factor against its own exact average
            const LightSample& ls = t.samples[t.sampleIndex[f]];
            double ex = 0, un = 0;
            const int points = 400;
            for (int q = 0; q < points; ++q) {
              Sampler sq(7, j, uint64_t(q));
              const Vec3 x = test::samplePatch(p, sq.next2D());
              const Color c = test::unoccludedSampleIrradiance(ls, x, p.normal, &desc.lights[ls.light]);
              const double cu = (double(c.x) + c.y + c.z) / 3.0;
              un += cu;
              const Vec3 o = x + p.normal * 1e-5f;
              const Vec3 dd = ls.position - o;
              if (cu > 0 && !fsScene.occluded(Ray(o, glm::normalize(dd), 0.0f, glm::length(dd) * (1.0f - 1e-5f)))) ex += cu;
            }
            const Color e = ls.emission * t.factor[f];
            fmt::print("      sample {} ({}): table {:.4g}  exact {:.4g}  unoccluded {:.4g}  V {:.4f}\n", t.sampleIndex[f],
                       desc.lights[ls.light].name, (double(e.x) + e.y + e.z) / 3.0, ex / points, un / points,
                       t.visible.empty() ? -1.0 : double(t.visible[f]));
          }
          fmt::print("    patch {} shape {} area {:.4f} centroid ({:.2f} {:.2f} {:.2f}): {:+.4f}% (exact mean {:.4g}, diff {:.4g} ± {:.2g})\n",
                     j, p.shape, p.area, p.centroid.x, p.centroid.y, p.centroid.z, 100 * p.area * dm[j] / total, mc[j], dm[j], ds[j]);
        }
      }
      fmt::print("  per point{}, all shapes: first-shot - exact = {:+.4f}% ± {:.4f}% of all power\n",
                 exposed ? " (exposed points)" : "", 100 * all / total, 100 * std::sqrt(allVar) / total);
    }
    double tab[3] = {0, 0, 0}, ref[3] = {0, 0, 0}, var[3] = {0, 0, 0};
    int count[3] = {0, 0, 0};
    for (uint32_t j = 0; j < n; ++j) {
      const Patch& p = t.mesh.patches[j];
      const int c = std::min(2, borderEdges(desc, p));
      const Color e = side[2 * size_t(j)];
      tab[c] += p.area * (double(e.x) + e.y + e.z) / 3.0;
      ref[c] += p.area * mc[j];
      var[c] += p.area * p.area * mcSe[j] * mcSe[j];
      ++count[c];
    }
    if (std::getenv("FSBIAS_WORST")) {
      std::vector<uint32_t> order(n);
      for (uint32_t j = 0; j < n; ++j) order[j] = j;
      auto rel = [&](uint32_t j) {
        const Color e = side[2 * size_t(j)];
        return mc[j] > 0 ? (double(e.x) + e.y + e.z) / 3.0 / mc[j] - 1 : 0.0;
      };
      auto power = [&](uint32_t j) { return std::abs(rel(j) * mc[j] * t.mesh.patches[j].area); };
      std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return power(x) > power(y); });
      std::vector<double> dShape(desc.shapes.size()), vShape(desc.shapes.size()), rShape(desc.shapes.size());
      for (uint32_t j = 0; j < n; ++j) {
        const Patch& p = t.mesh.patches[j];
        const Color e = side[2 * size_t(j)];
        dShape[p.shape] += p.area * ((double(e.x) + e.y + e.z) / 3.0 - mc[j]);
        rShape[p.shape] += p.area * mc[j];
        vShape[p.shape] += p.area * p.area * mcSe[j] * mcSe[j];
      }
      double total = 0;
      for (double r : rShape) total += r;
      for (size_t k = 0; k < desc.shapes.size(); ++k)
        fmt::print("  shape {:2} {:20}: table - MC = {:+.4f}% ± {:.4f}% of all power\n", k, desc.shapes[k].name,
                   100 * dShape[k] / total, 100 * std::sqrt(vShape[k]) / total);
      for (int k = 0; k < std::atoi(std::getenv("FSBIAS_WORST")); ++k) {
        const uint32_t j = order[k];
        const Patch& p = t.mesh.patches[j];
        fmt::print("  patch {} shape {} centroid ({:.4f},{:.4f},{:.4f}) area {:.2e} mc {:.4f} ± {:.4f} rel {:+.3f} border {}\n", j,
                   p.shape, p.centroid.x, p.centroid.y, p.centroid.z, p.area, mc[j], mcSe[j], rel(j), borderEdges(desc, p));
      }
    }
    {  // flux: Σ_j A_j r_ij per sample, 1 (point) or π (area vertex, ÷ S_i/3) in a closed room
      std::vector<double> flux(t.samples.size(), 0.0);
      for (uint32_t j = 0; j < n; ++j)
        for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k) flux[t.sampleIndex[k]] += t.mesh.patches[j].area * t.factor[k];
      double lo = 1e9, hi = -1e9, sum = 0;
      for (size_t i = 0; i < flux.size(); ++i) {
        const LightSample& ls = t.samples[i];
        const double f = ls.kind == LightSampleKind::AreaVertex ? flux[i] / ls.weight / kPi : flux[i];
        lo = std::min(lo, f), hi = std::max(hi, f), sum += f;
      }
      fmt::print("  flux per sample / exact: min {:.5f} mean {:.5f} max {:.5f}\n", lo, sum / flux.size(), hi);
    }
    const char* names[3] = {"interior", "edge", "corner"};
    double tt = 0, rr = 0, vv = 0;
    for (int c = 0; c < 3; ++c) {
      tt += tab[c], rr += ref[c], vv += var[c];
      if (ref[c] > 0)
        fmt::print("  {:8} {:5} patches: table {:+.3f}% ± {:.3f}% of MC\n", names[c], count[c],
                   100 * (tab[c] / ref[c] - 1), 100 * std::sqrt(var[c]) / ref[c]);
    }
    fmt::print("  all: table {:+.3f}% ± {:.3f}% of MC\n", 100 * (tt / rr - 1), 100 * std::sqrt(vv) / rr);
  }
}

