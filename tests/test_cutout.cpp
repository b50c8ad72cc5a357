// Alpha cut-outs: a screen whose checker alpha texture has half its area absent, between a directional
// light straight down and a floor. Rays pass its holes (closest hits, occlusion, the preprocessor's item-buffer
// rays); sensors under a hole read E and under a solid cell 0; the floor's images are ρ/π·E/2 by NEE, the
// first-shot table, light tracing and BDPT; blend mode lets 1 − α through; images do not depend on the thread
// count; bad alpha keys are errors naming the file, material and key (exit 2).
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/formats/json/scene_json.h"
#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/patches/patch_cutouts.h"
#include "common/util/error.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/gl/gl_item_buffer.h"
#include "preprocess/preprocessor.h"
#include "render/sensors/sensors.h"
#include "render_util.h"
#include "shipped_first_shot.h"
#include "test_util.h"

using namespace firstshot;

namespace {

constexpr double kE = 100.0;  // W/m² on a plane facing the light

/// Whether the screen exists above floor point (x, z): the checker's cells are 0.25 m squares, solid where the
/// texture's alpha (bilinear between texel centres) is ≥ ½, i.e. where both coordinates' half-periods agree
/// (u' = 12·(z + 3)/6, v' = 12·(3 − x)/6 on the built-in quad's coordinates).
bool solidAt(double x, double z) {
  const double fu = 2 * (z + 3) - std::floor(2 * (z + 3)), fv = 2 * (3 - x) - std::floor(2 * (3 - x));
  return (fu < 0.5) == (fv < 0.5);
}

/// A 2 × 2 checker of alpha 1 and 0 (RGB white), tiled 12 times across the screen.
std::shared_ptr<const Texture> checker() {
  TexelImage im = makeTexelImage(2, 2, std::vector<Color>(4, Color(1.0f)), "checker");
  im.alpha = {1.0f, 0.0f, 0.0f, 1.0f};
  auto t = std::make_shared<Texture>();
  t->image = std::make_shared<const TexelImage>(std::move(im));
  t->transform.scale = Vec2(12.0f);
  return t;
}

/// A floor [-2, 2]² at y = 0 of albedo @p rho under a black screen [-3, 3]² at y = 1 with the alpha keys @p alpha
/// (JSON members), and the checker as its alpha texture when @p textured; a directional light of kE straight down;
/// the camera at y = 0.8 looking down sees exactly the floor's [-0.5, 0.5]² (four cells each way).
SceneDesc screenOverFloor(double rho, const std::string& alpha = R"("alpha_mode": "mask")", bool textured = true) {
  const double fovY = 2 * std::atan(0.5 / 0.8) * 180 / kPi;
  SceneDesc desc = test::sceneFromJson(fmt::format(R"({{
    "camera": {{"position": [0, 0.8, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": {:.12f}, "resolution": [16, 16]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": {}}}, "screen": {{"type": "diffuse", "albedo": 0, {}}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]}},
               {{"type": "quad", "material": "screen", "vertices": [[-3, 1, -3], [-3, 1, 3], [3, 1, 3], [3, 1, -3]]}}],
    "lights": [{{"type": "directional", "direction": [0, -1, 0], "irradiance": {}}}],
    "settings": {{"patch_size": 0.5, "item_buffer_resolution": 64}}}})",
                                                   fovY, rho, alpha, kE));
  if (textured) desc.materials[size_t(desc.findMaterial("screen"))].alphaTexture = checker();
  return desc;
}

FirstShotTable tableOf(const SceneDesc& desc, const std::string& backend = "gl") {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = backend;
  po.quiet = true;
  return preprocessScene(desc, po);
}

void expectWithin(double value, double expected, double se, double slack, const std::string& what) {
  EXPECT_LE(std::abs(value - expected), 3 * se + slack * expected) << what << ": " << value << " vs " << expected << " ± " << se;
}

}  // namespace

// Rays straight down from above the screen: through a hole they reach the floor (t = 2), on a solid cell they
// stop at the screen (t = 1); occlusion and transmittance agree.
TEST(Cutout, RaysPassThroughHoles) {
  const RenderScene scene(screenOverFloor(0.5));
  ASSERT_NE(scene.cutouts(), nullptr);
  int holes = 0, solid = 0;
  for (int i = 0; i < 16; ++i)
    for (int k = 0; k < 16; ++k) {
      const double x = -1.0 + (i + 0.5) / 8.0, z = -1.0 + (k + 0.5) / 8.0;  // cell centres and between
      Ray ray{Vec3(float(x), 2.0f, float(z)), Vec3(0, -1, 0), 0.0f, 1e30f};
      Hit hit;
      ASSERT_TRUE(scene.intersect(ray, hit));
      const bool s = solidAt(x, z);
      EXPECT_NEAR(hit.t, s ? 1.0f : 2.0f, 1e-4f) << x << ", " << z;
      ray.tmax = 1.5f;
      EXPECT_EQ(scene.occluded(ray), s) << x << ", " << z;
      EXPECT_EQ(scene.transmittance(ray).x, s ? 0.0f : 1.0f) << x << ", " << z;
      (s ? solid : holes) += 1;
    }
  EXPECT_EQ(holes, solid);
}

// A sensor on the floor reads E under a hole and nothing under a solid cell (NEE; the floor and screen black).
TEST(Cutout, SensorsUnderHolesAndSolidCells) {
  const RenderScene scene(screenOverFloor(0.0));
  std::vector<Sensor> sensors;
  for (int i = 0; i < 8; ++i) sensors.push_back({Vec3(-0.875f + 0.25f * float(i), 0, 0.125f + 0.25f * float(i % 3)), Vec3(0, 1, 0)});
  auto integrator = test::preprocessedIntegrator("path", IntegratorOptions(), scene);
  SensorOptions so;
  so.samples = 64;
  const auto res = estimateSensors(*integrator, scene, sensors, so);
  for (size_t k = 0; k < sensors.size(); ++k)
    EXPECT_NEAR(res[k].irradiance.x, solidAt(sensors[k].p.x, sensors[k].p.z) ? 0.0 : kE, 1e-3 * kE) << k;
}

// The preprocessor's rays (the Embree item buffer and its exact point tests) see through the holes: half of a
// grid of rays straight down meets the screen; without the cut-outs all of them do. The item buffers of both back
// ends (an orthographic view straight down, 8 pixels a cell) show the screen at exactly half the pixels, and the
// floor through the holes; in blend mode (uniform alpha 0.3, no texture) at 0.3 of them within 4σ. The default
// and "auto" take Embree for such a scene (faster on llvmpipe), "gl" asked for is honoured.
TEST(Cutout, ItemBufferRaysSeeThroughHoles) {
  const SceneDesc desc = screenOverFloor(0.5);
  const PatchMesh mesh = buildPatches(desc, 0.5);
  ItemGeometry geometry = ItemGeometry::fromPatches(mesh);
  geometry.cutouts = PatchCutouts::build(desc, mesh);
  ASSERT_NE(geometry.cutouts, nullptr);
  const uint32_t screen = uint32_t(desc.findMaterial("screen"));
  for (bool cut : {true, false}) {
    ItemGeometry g = geometry;
    if (!cut) g.cutouts = nullptr;
    const EmbreeItemBuffer rays(g, geometry.bounds);
    int onScreen = 0, n = 0;
    for (int i = 0; i < 32; ++i)
      for (int k = 0; k < 32; ++k, ++n) {
        double t = 0;
        const uint32_t p = rays.firstHit(Vec3d(-1 + (i + 0.5) / 16, 2, -1 + (k + 0.5) / 16), Vec3d(0, -1, 0), 10, t);
        ASSERT_NE(p, kNoPatch);
        onScreen += mesh.patches[p].material == screen;
      }
    EXPECT_EQ(onScreen, cut ? n / 2 : n) << (cut ? "cut-out" : "opaque");
  }
  View view;
  view.projection = Projection::Orthographic;
  view.eye = Vec3d(0, 2, 0), view.forward = Vec3d(0, -1, 0), view.right = Vec3d(1, 0, 0), view.up = Vec3d(0, 0, -1);
  view.width = view.height = 64;
  const SceneDesc blendDesc = screenOverFloor(0.5, R"("alpha_mode": "blend", "alpha": 0.3)", false);
  const PatchMesh blendMesh = buildPatches(blendDesc, 0.5);
  ItemGeometry blend = ItemGeometry::fromPatches(blendMesh);
  blend.cutouts = PatchCutouts::build(blendDesc, blendMesh);
  for (const std::string backend : {"gl", "embree"}) {
    for (bool isBlend : {false, true}) {
      const ItemGeometry& g = isBlend ? blend : geometry;
      const PatchMesh& m = isBlend ? blendMesh : mesh;
      std::unique_ptr<ItemBufferRenderer> r;
      if (backend == "gl")
        r = std::make_unique<GLItemBuffer>(g, g.bounds);
      else
        r = std::make_unique<EmbreeItemBuffer>(g, g.bounds);
      std::vector<uint32_t> ids;
      r->render(view, ids);
      int onScreen = 0, onFloor = 0, wrong = 0;
      for (int j = 0; j < view.height; ++j)
        for (int i = 0; i < view.width; ++i) {
          const uint32_t p = ids[size_t(j) * size_t(view.width) + size_t(i)];
          ASSERT_NE(p, kNoPatch);
          const bool s = m.patches[p].material == screen;
          (s ? onScreen : onFloor) += 1;
          const Vec2d uv = view.pixelCentre(i, j);  // x = u, z = −v
          if (!isBlend && s != solidAt(uv.x, -uv.y)) ++wrong;
        }
      const double n = double(view.pixelCount());
      if (isBlend)
        EXPECT_NEAR(onScreen / n, 0.3, 4 * std::sqrt(0.3 * 0.7 / n)) << backend << " blend";
      else
        EXPECT_EQ(wrong, 0) << backend << ": " << onScreen << " on the screen, " << onFloor << " on the floor";
    }
  }
  SettingsOverrides cli;
  EXPECT_EQ(resolveSettings(desc, cli).backend, "embree");
  cli.backend = "auto";
  EXPECT_EQ(resolveSettings(desc, cli).backend, "embree");
  cli.backend = "gl";
  EXPECT_EQ(resolveSettings(desc, cli).backend, "gl");
}

// The floor seen from under the screen, direct light only: L = ρ/π·E/2 (half the floor under holes), by NEE, by
// the first-shot table at the camera's hits (the table's factors see through the holes), by light tracing and
// by BDPT.
TEST(Cutout, ImagesOfTheFloorUnderTheScreen) {
  const double rho = 0.5, expected = rho / kPi * 0.5 * kE;
  const SceneDesc desc = screenOverFloor(rho);
  const RenderScene plain(desc);
  const RenderScene tabled(desc, tableOf(desc));  // GL item buffers
  const RenderScene tabledEmbree(desc, tableOf(desc, "embree"));
  IntegratorOptions io;
  io.maxDepth = 1;
  struct Case {
    const char* integrator;
    const RenderScene* scene;
    PrimaryMode primary;
  };
  for (const Case& c : {Case{"path", &plain, PrimaryMode::Exact}, Case{"path", &tabled, PrimaryMode::Patch},
                        Case{"path", &tabledEmbree, PrimaryMode::Patch},
                        Case{"light", &plain, PrimaryMode::Exact}, Case{"bdpt", &plain, PrimaryMode::Exact}}) {
    const std::string what = fmt::format("{}{}", c.integrator, c.scene == &tabled ? " with the GL table" : c.scene == &tabledEmbree ? " with the Embree table" : "");
    io.primary = c.primary;
    io.lightPathsPerPixel = std::string(c.integrator) == "light" ? 64 : 0;
    auto integrator = test::preprocessedIntegrator(c.integrator, io, *c.scene);
    const test::RenderRun run = test::renderWith(*integrator, *c.scene, 128);
    double mean = 0, se = 0;
    test::imageMean(run.film, 0, mean, se);
    fmt::print("{}: {:.5f} ± {:.5f}, expected {:.5f}\n", what, mean, se, expected);
    expectWithin(mean, expected, se, c.scene != &plain ? 0.01 : 1e-4, what);
  }
}

// Blend: a uniform alpha of 0.3 lets 0.7·E through on average: the floor's image (camera rays jittered over the
// pixels, so the shadow rays differ from sample to sample) is ρ/π·0.7·E by NEE and by BDPT. (A sensor's shadow ray
// to a directional light repeats exactly, and so does its coin: blend dithers over positions, not per point.)
TEST(Cutout, BlendLetsOneMinusAlphaThrough) {
  const double rho = 0.5, expected = rho / kPi * 0.7 * kE;
  const RenderScene scene(screenOverFloor(rho, R"("alpha_mode": "blend", "alpha": 0.3)", false));
  IntegratorOptions io;
  io.maxDepth = 1;
  for (const char* name : {"path", "bdpt"}) {
    auto integrator = test::preprocessedIntegrator(name, io, scene);
    const test::RenderRun run = test::renderWith(*integrator, scene, 256);
    double mean = 0, se = 0;
    test::imageMean(run.film, 0, mean, se);
    fmt::print("blend, {}: {:.5f} ± {:.5f}, expected {:.5f}\n", name, mean, se, expected);
    expectWithin(mean, expected, se, 1e-4, name);
  }
}

// The coin is a hash of the ray and the patch: 1 thread and 2 threads give the same image, pixel for pixel.
TEST(Cutout, ImagesIndependentOfThreads) {
  const RenderScene scene(screenOverFloor(0.5, R"("alpha_mode": "blend", "alpha": 0.6)"));
  IntegratorOptions io;
  auto integrator = test::preprocessedIntegrator("path", io, scene);
  const test::RenderRun one = test::renderWith(*integrator, scene, 16, 1, 1);
  const test::RenderRun two = test::renderWith(*integrator, scene, 16, 1, 2);
  for (int y = 0; y < one.film.height(); ++y)
    for (int x = 0; x < one.film.width(); ++x) ASSERT_EQ(one.film.mean(x, y), two.film.mean(x, y)) << x << ", " << y;
}

// Bad alpha keys name the file, the material and the key; the tools exit with 2.
TEST(Cutout, BadInput) {
  const auto message = [](const std::string& material) {
    try {
      parseSceneJson(fmt::format(R"({{"materials": {{"m": {}}}, "shapes": []}})", material), "bad.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(R"({"type": "diffuse", "alpha_mode": "mask", "alpha_cutoff": 1.5})"),
            "bad.json: materials.m.alpha_cutoff: must be in [0, 1] (got 1.500000)");
  EXPECT_EQ(message(R"({"type": "diffuse", "alpha_mode": "fuzzy"})"),
            "bad.json: materials.m.alpha_mode: unknown alpha mode \"fuzzy\" (opaque, mask, blend)");
  EXPECT_EQ(message(R"({"type": "mirror", "alpha_mode": "mask"})"),
            "bad.json: materials.m.alpha_mode: alpha keys apply to diffuse, glossy and pbr materials");
  const std::string missing = message(R"({"type": "pbr", "alpha_mode": "mask", "alpha_texture": "nowhere.png"})");
  EXPECT_NE(missing.find("materials.m.alpha_texture: material \"m\""), std::string::npos) << missing;
  EXPECT_NE(missing.find("nowhere.png"), std::string::npos) << missing;
  const std::string dir = test::tempDir();
  test::writeText(dir + "/bad.json", R"({"materials": {"m": {"type": "diffuse", "alpha_mode": "mask", "alpha": -1}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]]}]})");
  const test::CommandResult r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " " + dir + "/bad.json -o " + dir + "/x.fsd");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("materials.m.alpha"), std::string::npos) << r.output;
}

// First-shot against NEE in the shipped scenes/cutout-screen.json (a small area light through a perforated
// screen onto a table): the path tracer with and without the table, every light sampled at every vertex, on
// the same camera samples; the image mean of the difference within 0.3% + 3σ of the NEE image's mean.
TEST(Cutout, ShippedScreenFirstShotAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("Cutout.ImagesOfTheFloorUnderTheScreen");
  test::expectShippedSceneFirstShotAgreesWithNee("cutout-screen");
}

// The same with the table from the GL back end, whose fragment shader discards the screen's holes.
TEST(Cutout, ShippedScreenFirstShotAgreesWithNeeGL) {
  FIRSTSHOT_STATISTICS_ONLY("Cutout.ImagesOfTheFloorUnderTheScreen");
  test::expectShippedSceneFirstShotAgreesWithNee("cutout-screen", "gl");
}

// The same scene with the table by light tracing, BDPT and the irradiance cache against the path tracer's NEE
// image (independent renders): each image mean within 0.3% + 3σ of it.
TEST(Cutout, ShippedScreenShootingIntegratorsAgreeWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("Cutout.ImagesOfTheFloorUnderTheScreen");
  test::expectTableIntegratorsAgreeWithNee("cutout-screen", loadScene(test::source("scenes/cutout-screen.json")));
}

// Imported assets: glTF's alphaMode, alphaCutoff and baseColorFactor's alpha; OBJ/MTL's map_d (a mask of alpha
// d × the texture's alpha channel); an emitting glTF material stays opaque.
TEST(Cutout, ImportedAlpha) {
  const std::string dir = test::tempDir();
  const auto gltf = [&](const std::string& material) {
    test::writeText(dir + "/t.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
      "materials": [)" + material + R"(],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/"}]})");
    const SceneDesc s = loadScene(dir + "/t.gltf");
    for (const ShapeDesc& shape : s.shapes) return s.materials[size_t(shape.material)];
    return MaterialDesc();
  };
  const MaterialDesc mask = gltf(R"({"alphaMode": "MASK", "alphaCutoff": 0.25, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.4]}})");
  EXPECT_EQ(mask.alphaMode, AlphaMode::Mask);
  EXPECT_FLOAT_EQ(mask.alphaCutoff, 0.25f);
  EXPECT_FLOAT_EQ(mask.alpha, 0.4f);
  EXPECT_EQ(gltf(R"({"alphaMode": "BLEND"})").alphaMode, AlphaMode::Blend);
  EXPECT_EQ(gltf(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.4]}})").alphaMode, AlphaMode::Opaque);
  EXPECT_EQ(gltf(R"({"alphaMode": "MASK", "emissiveFactor": [1, 1, 1]})").alphaMode, AlphaMode::Opaque);

  std::filesystem::copy_file(test::source("scenes/textures/perforated.png"), dir + "/holes.png");
  test::writeText(dir + "/m.mtl", "newmtl sheet\nKd 0.5 0.5 0.5\nd 0.9\nmap_d holes.png\n");
  test::writeText(dir + "/m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                  "usemtl sheet\nf 1/1 2/2 3/3 4/4\n");
  const SceneDesc obj = loadScene(dir + "/m.obj");
  const MaterialDesc& sheet = obj.materials[size_t(obj.shapes.at(0).material)];
  EXPECT_EQ(sheet.alphaMode, AlphaMode::Mask);
  EXPECT_NEAR(sheet.alpha, 0.9f, 1e-6f);
  ASSERT_TRUE(sheet.alphaTexture);
  EXPECT_EQ(sheet.alphaTexture->image->alpha.size(), size_t(64 * 64));  // the PNG's alpha channel, not its grey
  // Half the sheet is holes: rays straight down on a grid meet it half the time.
  const RenderScene scene(obj);
  int hits = 0;
  for (int i = 0; i < 64; ++i)
    for (int k = 0; k < 64; ++k) {
      Hit hit;
      hits += scene.intersect(Ray(Vec3((i + 0.5f) / 64, 1, -(k + 0.5f) / 64), Vec3(0, -1, 0)), hit);
    }
  EXPECT_NEAR(hits / 4096.0, 0.5, 0.03);
}
