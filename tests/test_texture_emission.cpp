// Emission per point: scenes/emissive-texture.json, a ceiling panel whose emission texture is white on its
// left half and black on its right, over a floor. What a ray sees at two texture coordinates (and on a glTF's
// emissiveTexture); the floor's irradiance
// under each half against a quadrature of the panel, by NEE (sensors) and by BSDF (cosine) sampling; the
// preprocessor's light samples weighted by the texture with the right total; light tracing and BDPT against the path
// tracer; first-shot against NEE for the path tracer, light tracing, BDPT and the cache; 1 and 2 threads alike.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "common/materials/emission_texture.h"
#include "common/sampling/sampling.h"
#include "common/util/error.h"
#include "preprocess/light_tessellation.h"
#include "render/output/image_io.h"
#include "render/sensors/sensors.h"
#include "tests/bias_util.h"
#include "tests/block_compare.h"
#include "tests/render_util.h"
#include "tests/shipped_first_shot.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

constexpr double kLe = 40.0;      // the panel's emission factor, W/(m² sr)
constexpr double kHeight = 1.2;   // the panel's height over the floor, m
constexpr double kHalf = 0.3;     // the panel's half width, m

SceneDesc panelScene() { return loadScene(test::source("scenes/emissive-texture.json")); }

/// The scene seen from its camera lowered to the floor and the wall, the panel out of the frame: the images then hold
/// the light the panel sends, not its own sharp half-lit rectangle (whose pixel noise would swamp the comparisons).
SceneDesc floorView() {
  SceneDesc d = panelScene();
  d.camera.lookAt = Vec3d(0, 0.3, 0), d.camera.fovYDeg = 30;
  return d;
}

/// The panel's material and shape index in @p d.
const MaterialDesc& panelMaterial(const SceneDesc& d) { return d.materials.at(size_t(d.findMaterial("panel"))); }
int panelShape(const SceneDesc& d) {
  for (size_t i = 0; i < d.shapes.size(); ++i)
    if (d.shapes[i].material == d.findMaterial("panel")) return int(i);
  return -1;
}

/// The irradiance (W/m²) of floor point (x, 0, z), normal +y, from the panel: ∫ Le(y) h²/r⁴ dA by a midpoint rule,
/// Le(y) read through the material as the renderer does (emissionAt at u = (x + 0.3)/0.6).
double quadratureIrradiance(const MaterialDesc& m, double x, double z) {
  const int n = 400;
  const double cell = 2 * kHalf / n;
  double e = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      const double px = -kHalf + (i + 0.5) * cell, pz = -kHalf + (k + 0.5) * cell;
      const double le = emissionAt(m, Vec2(float((px + kHalf) / (2 * kHalf)), float((pz + kHalf) / (2 * kHalf)))).x;
      const double r2 = (px - x) * (px - x) + kHeight * kHeight + (pz - z) * (pz - z);
      e += le * kHeight * kHeight / (r2 * r2) * cell * cell;
    }
  return e;
}

TEST(EmissionTexture, RadianceSeenAtTwoTextureCoordinates) {
  // Rays straight up meet the panel at u = (x + 0.3)/0.6: white (Le = 40) at x = −0.2, black at x = +0.2, and half
  // way (the bilinear texels 7 and 8) at x = 0; the mean over the panel is the material's emission (its power).
  const SceneDesc desc = panelScene();
  const RenderScene scene(desc);
  EXPECT_NEAR(panelMaterial(desc).emission.x, kLe / 2, 1e-4);
  for (const auto& [x, expected] : {std::pair{-0.2, kLe}, std::pair{0.2, 0.0}, std::pair{0.0, kLe / 2}}) {
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray(Vec3(float(x), 0.5f, 0.05f), Vec3(0, 1, 0)), hit));
    ASSERT_FALSE(hit.onPatch());
    EXPECT_NEAR(scene.lights().emitted(hit, Vec3(0, -1, 0)).x, expected, 1e-3 * kLe) << "x = " << x;
    EXPECT_EQ(scene.lights().emitted(hit, Vec3(0, 1, 0)), Color(0.0f)) << "one-sided";
  }
}

TEST(EmissionTexture, GltfEmissiveTextureEmitsPerPoint) {
  // A glTF quad at y = 1 facing down, u = x, v = z, emissiveFactor 3 × a 2 × 1 texture (white, black; repeat): rays up
  // meet Le = 3 at u = ¼ (texel 0's centre) and 0 at u = ¾; the material's emission is the mean, 1.5.
  const std::string dir = test::tempDir();
  const uint8_t rgb[6] = {255, 255, 255, 0, 0, 0};
  image::writePng(dir + "/e.png", 2, 1, rgb);
  const std::vector<float> positions = {0, 1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 1}, uv = {0, 0, 1, 0, 1, 1, 0, 1};
  const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(positions.data()), positions.size() * 4);
  bin.append(reinterpret_cast<const char*>(uv.data()), uv.size() * 4);
  bin.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 2);
  test::writeText(dir + "/q.bin", bin);
  test::writeText(dir + "/q.gltf", fmt::format(R"({{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}], "materials": [{{"emissiveFactor": [3, 3, 3], "emissiveTexture": {{"index": 0}}}}],
  "textures": [{{"source": 0}}], "images": [{{"uri": "e.png"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "indices": 2, "material": 0}}]}}],
  "buffers": [{{"uri": "q.bin", "byteLength": {}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 1, 0], "max": [1, 1, 1]}},
                {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}})", bin.size()));
  const SceneDesc desc = loadScene(dir + "/q.gltf");
  const MaterialDesc& m = desc.materials.at(size_t(desc.shapes.at(0).material));
  ASSERT_TRUE(m.emissionTexture);
  EXPECT_NEAR(m.emission.x, 1.5, 1e-5);
  const RenderScene scene(desc);
  for (const auto& [x, expected] : {std::pair{0.25f, 3.0}, std::pair{0.75f, 0.0}}) {
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray(Vec3(x, 0, 0.5f), Vec3(0, 1, 0)), hit));
    EXPECT_NEAR(scene.lights().emitted(hit, Vec3(0, -1, 0)).x, expected, 1e-4) << "u = " << x;
  }
}

TEST(EmissionTexture, MissingImageNamesTheFileMaterialAndKey) {
  // The shipped scene copied where its texture is not (relative to the scene file).
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", test::readFile(test::source("scenes/emissive-texture.json")));
  try {
    loadScene(dir + "/scene.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const char* part : {"scene.json", "materials.panel.emission_texture", "half_white.png", "not found"})
      EXPECT_NE(what.find(part), std::string::npos) << what;
  }
}

TEST(EmissionTexture, FloorIrradianceFollowsTheTexture) {
  // The floor under the panel, the wall black (direct light only). At x = ∓0.4 the irradiance is the quadrature's,
  // by the sensors' NEE and by cosine-distributed (BSDF) rays that meet the panel; the white side gets more.
  SceneDesc desc = panelScene();
  desc.materials.at(size_t(desc.findMaterial("wall"))).albedo = Color(0.0f);  // the back wall reflects nothing
  const RenderScene scene(desc);
  const MaterialDesc& m = panelMaterial(desc);
  auto integrator = test::preprocessedIntegrator("path", IntegratorOptions(), scene);
  SensorOptions so;
  so.samples = 4096;
  const std::vector<Vec3> points = {Vec3(-0.4f, 0, 0.1f), Vec3(0.4f, 0, 0.1f)};
  const auto nee = estimateSensors(*integrator, scene, {{points[0], Vec3(0, 1, 0)}, {points[1], Vec3(0, 1, 0)}}, so);
  std::vector<double> expected;
  for (size_t i = 0; i < points.size(); ++i) {
    expected.push_back(quadratureIrradiance(m, points[i].x, points[i].z));
    const double e = nee[i].irradiance.x, se = nee[i].stderrLux / so.efficacy;
    // BSDF sampling: cosine-distributed rays (pdf cosθ/π), E ≈ π · mean of the emitted radiance they meet.
    const int n = 256;
    double sum = 0, sum2 = 0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const Vec3 local = squareToCosineHemisphere(Vec2((a + 0.5f) / n, (b + 0.5f) / n));
        const Vec3 d(local.x, local.z, local.y);  // about +y
        Hit hit;
        double l = 0;
        if (scene.intersect(Ray(points[i] + Vec3(0, 1e-4f, 0), d), hit) && !hit.onPatch())
          l = kPi * scene.lights().emitted(hit, -d).x;
        sum += l, sum2 += l * l;
      }
    const double bsdf = sum / (n * n), seBsdf = std::sqrt(std::max(0.0, sum2 / (n * n) - bsdf * bsdf) / (n * n));
    fmt::print("x = {:+.1f}: quadrature {:.5f}, NEE {:.5f} ± {:.5f}, BSDF {:.5f} ± {:.5f}\n", points[i].x, expected[i], e,
               se, bsdf, seBsdf);
    EXPECT_LE(std::abs(e - expected[i]), 4 * se + 1e-6) << "NEE at x = " << points[i].x;
    EXPECT_LE(std::abs(bsdf - expected[i]), 4 * seBsdf + 2e-3 * expected[i]) << "BSDF at x = " << points[i].x;
  }
  // The white side gets a third more at 1.2 m (a uniform panel of the mean radiance would light both alike).
  EXPECT_GT(expected[0], 1.25 * expected[1]);
  EXPECT_GT(nee[0].irradiance.x, 1.2 * nee[1].irradiance.x);
}

TEST(EmissionTexture, LightSamplesFollowTheTexture) {
  // The preprocessor's samples of the panel: Σ weight·emission = ∫ Le dA = 40 × 0.36 m² × ½ (the clamped bilinear
  // texture is symmetric about u = ½), and a sample under the white half emits more than its mirror image.
  const SceneDesc desc = panelScene();
  const LightTessellation t = tessellateAreaLight(desc, panelShape(desc), 0, desc.settings.lightTolerance);
  ASSERT_EQ(t.emission.size(), t.positions.size());
  double power = 0, white = 0, black = 0;
  for (size_t i = 0; i < t.positions.size(); ++i) {
    power += t.weights[i] * t.emission[i].x;
    if (t.positions[i].x < -0.1) white += t.weights[i] * t.emission[i].x;
    if (t.positions[i].x > 0.1) black += t.weights[i] * t.emission[i].x;
  }
  fmt::print("{} samples: Σ w·Le = {:.6f} (expected {:.6f}); x < −0.1: {:.4f}, x > 0.1: {:.4f}\n", t.positions.size(),
             power, kLe * 0.36 / 2, white, black);
  EXPECT_NEAR(power, kLe * 0.36 / 2, 1e-3 * kLe * 0.36 / 2);
  EXPECT_GT(white, 0.0);
  EXPECT_LT(black, 0.02 * white);  // the ramp between texels 7 and 8 reaches x = 0.019 m
}

// One TEST per integrator, as in test_shading_normals.cpp: scenes, sample counts and statistics gates differ.
TEST(EmissionTexture, LightTracingAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("EmissionTexture.FloorIrradianceFollowsTheTexture");
  test::expectAgreesWithPathTracing("light", "emissive-texture", floorView(), 400, 200);
}

TEST(EmissionTexture, BdptAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("EmissionTexture.FloorIrradianceFollowsTheTexture");
  test::expectAgreesWithPathTracing("bdpt", "emissive-texture", floorView(), 200, 200);
}

TEST(EmissionTexture, FirstShotAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("EmissionTexture.FloorIrradianceFollowsTheTexture");
  test::expectShippedSceneFirstShotAgreesWithNee("emissive-texture");
}

TEST(EmissionTexture, ShootingIntegratorsAndCacheWithTheTableAgreeWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("EmissionTexture.FloorIrradianceFollowsTheTexture");
  test::expectTableIntegratorsAgreeWithNee("emissive-texture (floor view)", floorView());
}

TEST(EmissionTexture, TablesDirectLightFollowsTheTextureBlockByBlock) {
  // The table's direct light at the camera-visible points (primary patch, max depth 1) against NEE's, per 8 × 8 block:
  // light samples that emitted the panel's mean would light the floor alike on both sides, too little on the left
  // and too much on the right (the image mean alone would hardly see it).
  FIRSTSHOT_STATISTICS_ONLY("EmissionTexture.FloorIrradianceFollowsTheTexture");
  SceneDesc desc = floorView();
  desc.camera.width = 32, desc.camera.height = 24;
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree", po.settings.resolution = 128, po.quiet = true;
  const RenderScene tabled(desc, preprocessScene(desc, po)), plain(desc);
  IntegratorOptions io;
  io.maxDepth = 1;
  io.primary = PrimaryMode::Patch;
  const auto firstShot = test::preprocessedIntegrator("path", io, tabled), nee = test::preprocessedIntegrator("path", io, plain);
  test::expectBlocksAgree("emissive-texture, direct light", test::blockMeans(*firstShot, tabled, 16),
                          test::blockMeans(*nee, plain, 256));
}

TEST(EmissionTexture, ImagesIdenticalForOneAndTwoThreads) {
  SceneDesc desc = panelScene();
  desc.camera.width = 32, desc.camera.height = 24;
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene tabled(desc, preprocessScene(desc, po));
  test::expectSameImageForOneAndTwoThreads(tabled);
}

}  // namespace
