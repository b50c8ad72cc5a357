// Scenes nobody here wrote, at the defaults: the patch size from the scene's own geometry (the same
// patches in millimetres and kilometres), an emissive mesh sampled as its receivers need, whatever
// its triangle count.
#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/patches/patch_size.h"
#include "common/patches/patches.h"
#include "common/scene/scene_shapes.h"
#include "common/util/error.h"
#include "preprocess/light_samples.h"
#include "preprocess/light_tessellation.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/integrator.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"
#include "tests/bias_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

/// @p d with every length multiplied by @p s (vertices, light positions, the camera).
SceneDesc scaled(SceneDesc d, double s) {
  for (ShapeDesc& shape : d.shapes)
    for (Vec3d& v : shape.vertices) v *= s;
  for (LightDesc& l : d.lights) l.position *= s;
  d.camera.position *= s, d.camera.lookAt *= s;
  return d;
}

/// The shipped Cornell box as a scene that sets no patch size.
SceneDesc cornellWithoutPatchSize() {
  SceneDesc d = loadScene(test::source("scenes/cornell.json"));
  d.settings.patchSize = d.settings.minPatchSize = 0;
  d.camera.width = d.camera.height = 32;
  return d;
}

TEST(AutomaticPatchSize, BoundsTheCoarseCountAndScalesWithTheScene) {
  const SceneDesc d = cornellWithoutPatchSize();
  const double h = autoPatchSize(d), faces = countPatchPolygons(d, kFacesAsTheyAre);
  const double n = countPatchPolygons(d, h);
  EXPECT_LE(n, faces + kAutoPatchBudget);
  EXPECT_GT(countPatchPolygons(d, h * 0.999), faces + kAutoPatchBudget) << "not the largest size within the budget";
  EXPECT_GT(n, 0.9 * kAutoPatchBudget);  // steps of ceil(): the count lands close below the target
  for (double s : {1e-3, 1e3}) {
    const SceneDesc ds = scaled(d, s);
    EXPECT_NEAR(autoPatchSize(ds) / (s * h), 1.0, 1e-9) << "scale " << s;
    EXPECT_EQ(countPatchPolygons(ds, autoPatchSize(ds)), n) << "scale " << s;
    EXPECT_EQ(buildPatches(ds, resolvePatchSize(ds)).size(), buildPatches(d, h).size()) << "scale " << s;
  }
}

// A scene of more small faces than the budget (a finely tessellated sphere in the Cornell box): the
// sphere's faces stay whole, the box's walls are still cut, into at most the budget's patches.
TEST(AutomaticPatchSize, ManySmallFacesStayWholeWhileLargeOnesAreCut) {
  SceneDesc d = cornellWithoutPatchSize();
  ShapeDesc ball;
  ball.name = "ball";
  ball.type = ShapeType::Sphere;
  ball.material = d.shapes[0].material;
  shapes::makeSphere(ball, Vec3d(0.3, 0.1, 0.3), 0.05, 6);  // 81920 triangles, below 2 mm across
  const size_t before = d.shapes.size();
  d.shapes.push_back(ball);
  const double faces = countPatchPolygons(d, kFacesAsTheyAre), h = autoPatchSize(d);
  const PatchMesh mesh = buildPatches(d, h);
  EXPECT_LE(mesh.size(), faces + kAutoPatchBudget);
  EXPECT_GT(mesh.size(), faces + 0.9 * kAutoPatchBudget);
  size_t onBall = 0;
  for (const Patch& p : mesh.patches) onBall += p.shape == before;
  EXPECT_EQ(onBall, ball.faces.size()) << "the small faces are taken as they are";
  EXPECT_LT(h, 0.05) << "the walls are cut finer than a fifth of the box";
}

// The same scene in millimetres, metres and kilometres: the same table size and the same image. The
// light is an area light (radiance), so the image does not change with the unit.
TEST(AutomaticPatchSize, SameImageInMillimetresAndKilometres) {
  FIRSTSHOT_STATISTICS_ONLY("AutomaticPatchSize.BoundsTheCoarseCountAndScalesWithTheScene");
  const SceneDesc d = cornellWithoutPatchSize();
  std::vector<double> means;
  std::vector<size_t> patches;
  for (double s : {1e-3, 1.0, 1e3}) {
    const SceneDesc ds = scaled(d, s);
    const RenderScene scene(ds, test::preprocessDefault(ds));
    patches.push_back(scene.mesh().size());
    IntegratorOptions io;
    io.maxDepth = 3;
    double mean = 0, se = 0;
    test::imageMean(test::renderPath(scene, io, 16, 3).film, 1, mean, se);
    means.push_back(mean);
  }
  // The coarse meshes are the same (above); refinement decides a few borderline splits on float
  // vertices, which a factor of 1000 rounds differently.
  EXPECT_NEAR(double(patches[0]) / double(patches[1]), 1.0, 2e-3);
  EXPECT_NEAR(double(patches[2]) / double(patches[1]), 1.0, 2e-3);
  fmt::print("image means {:.6f} {:.6f} {:.6f}, {} patches after refinement\n", means[0], means[1], means[2], patches[1]);
  EXPECT_NEAR(means[0] / means[1], 1.0, 1e-3);
  EXPECT_NEAR(means[2] / means[1], 1.0, 1e-3);
}

/// A 4 × 3 × 4 m room (walls facing in) with an emissive icosphere of 20·4^@p subdivisions triangles,
/// radius 5 cm, hanging 1.2 m above the floor.
SceneDesc roomWithEmissiveSphere(int subdivisions) {
  SceneDesc d = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.6},
      "bulb": {"type": "diffuse", "albedo": 0, "emission": 200}},
    "shapes": [{"type": "box", "material": "white", "min": [-2,0,-2], "max": [2,3,2], "flip_normals": true},
               {"type": "sphere", "material": "bulb", "center": [0.3,1.2,-0.2], "radius": 0.05, "subdivisions": )" +
                             std::to_string(subdivisions) + R"(}],
    "camera": {"position": [1.8,1.6,1.8], "look_at": [-0.5,0.8,-0.5], "fov_y": 70, "resolution": [40, 30]}})");
  d.shapes[1].type = ShapeType::Mesh;  // any emissive mesh (a sphere is sampled inside: tests/test_sphere_light.cpp)
  return d;
}

/// Irradiance (W/m²) at @p x facing @p n from the light's samples (the vertex rule) and exactly.
std::pair<double, double> irradiance(const SceneDesc& d, const std::vector<LightSample>& samples, const Vec3d& x,
                                     const Vec3d& n) {
  double rule = 0, exact = 0;
  for (const LightSample& s : samples) {
    const Vec3d r = Vec3d(s.position) - x;
    const double dist = glm::length(r);
    rule += s.weight * std::max(0.0, glm::dot(n, r) / dist) * std::max(0.0, -glm::dot(Vec3d(s.normal), r) / dist) / (dist * dist);
  }
  const ShapeDesc& bulb = d.shapes[1];
  for (const Face& f : bulb.faces) {
    const Vec3d tri[3] = {bulb.vertices[f.v[0]], bulb.vertices[f.v[1]], bulb.vertices[f.v[2]]};
    if (glm::dot(x - tri[0], glm::cross(tri[1] - tri[0], tri[2] - tri[0])) > 0)  // x in front of the face
      exact += analytic::polygonCosineSolidAngle(x, n, tri, 3);
  }
  return {rule, exact};
}

// 1280, 5120 and 20480 triangles: about the same number of samples, far fewer than the vertices, and
// the irradiance they give on the walls and the floor within the tolerance of the exact one.
TEST(EmissiveMesh, SamplesFollowTheReceiversNotTheTriangles) {
  std::vector<size_t> counts;
  for (int sub : {3, 4, 5}) {
    const SceneDesc d = roomWithEmissiveSphere(sub);
    const uint32_t bulb = uint32_t(d.lights.size() - 1);
    ASSERT_EQ(d.lights[bulb].type, LightType::Area);
    const std::vector<LightSample> s = makeLightSamples(d, {bulb}, 0.0, d.settings.lightTolerance);
    counts.push_back(s.size());
    double weight = 0;
    for (const LightSample& x : s) weight += x.weight;
    const double kept = weight / shapeArea(d.shapes[1]);  // the power kept: all of it (a cluster weighs its area)
    EXPECT_NEAR(kept, 1.0, 1e-6);
    double worst = 0;
    for (double u : {-1.7, -0.6, 0.5, 1.6})
      for (double v : {-1.7, -0.4, 0.9, 1.8})
        for (const auto& [x, n] : {std::pair{Vec3d(u, 0, v), Vec3d(0, 1, 0)}, std::pair{Vec3d(u, 1 + 0.5 * v, -2), Vec3d(0, 0, 1)},
                                   std::pair{Vec3d(2, 1.5 + 0.5 * u, v), Vec3d(-1, 0, 0)}, std::pair{Vec3d(u, 3, v), Vec3d(0, -1, 0)}}) {
          const auto [rule, exact] = irradiance(d, s, x, n);
          worst = std::max(worst, std::abs(rule / exact - 1));
        }
    fmt::print("{} triangles, {} vertices: {} samples, worst relative irradiance error {:.2e}\n", d.shapes[1].faces.size(),
               d.shapes[1].vertices.size(), s.size(), worst);
    EXPECT_LT(worst, d.settings.lightTolerance);
    EXPECT_LT(s.size(), d.shapes[1].vertices.size() / 2);
  }
  EXPECT_LE(counts[2], counts[0] + counts[0] / 2) << "the count follows the receivers, not the mesh";
}

// The room lit by the 20480-triangle bulb: the first-shot image at the defaults (automatic patch
// size, samples by need) within 0.3% of path tracing with NEE to the bulb's triangles (3σ).
TEST(EmissiveMesh, FirstShotImageAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("EmissiveMesh.SamplesFollowTheReceiversNotTheTriangles");
  const SceneDesc d = roomWithEmissiveSphere(5);
  const RenderScene nee(d), fs(d, test::preprocessDefault(d));
  ASSERT_EQ(fs.firstShot()->replacedLights.size(), 1u) << "the bulb is a small light";
  IntegratorOptions io;
  io.maxDepth = 3;
  io.lightSampler = LightStrategy::All;
  auto a = makeIntegrator("path", io), b = makeIntegrator("path", io);
  a->preprocess(fs);
  b->preprocess(nee);
  const test::BiasMeasure m = test::measurePairedBias(*a, *b, nee, Camera(d.camera), 1024, 11);
  fmt::print("first-shot − NEE = {:+.3f}% ± {:.3f}% of the image mean\n", 100 * m.relative(), 100 * m.relativeSe());
  EXPECT_LT(std::abs(m.relative()) + 3 * m.relativeSe(), 0.003);
  EXPECT_LT(m.relativeSe(), 0.001);
}

// One settings route on the preprocess side: the scene's settings, the command line's on
// top, then the automatic patch sizes resolved, all in resolveSettings; each field one meaning.
TEST(PreprocessSettings, SceneThenCommandLineThenAutomaticSizes) {
  SceneDesc d = cornellWithoutPatchSize();
  const FirstShotSettings defaults;  // the documented defaults, as the scene's settings start
  FirstShotSettings s = resolveSettings(d);
  EXPECT_DOUBLE_EQ(s.patchSize, autoPatchSize(d));  // 0: automatic
  EXPECT_DOUBLE_EQ(s.minPatchSize, s.patchSize / kDefaultRefineRatio);  // 0: patchSize/16
  EXPECT_EQ(s.resolution, defaults.resolution);
  EXPECT_EQ(s.window, "hemicube");
  EXPECT_EQ(s.backend, "gl");
  EXPECT_EQ(s.estimator, "analytic");
  EXPECT_EQ(s.rotationSeed, 0u);
  EXPECT_DOUBLE_EQ(s.refineTolerance, defaults.refineTolerance);
  EXPECT_DOUBLE_EQ(s.lightPatchSize, 0.0);  // automatic light tessellation stays 0: a rule, not a length
  EXPECT_EQ(defaultOptions(d).settings.hash(), s.hash());

  // The scene's values.
  d.settings.patchSize = 0.2, d.settings.minPatchSize = 0.05, d.settings.resolution = 128, d.settings.window = "tetra";
  d.settings.lightTolerance = 0.03;
  s = resolveSettings(d);
  EXPECT_DOUBLE_EQ(s.patchSize, 0.2);
  EXPECT_DOUBLE_EQ(s.minPatchSize, 0.05);
  EXPECT_EQ(s.resolution, 128u);
  EXPECT_EQ(s.window, "tetra");
  EXPECT_DOUBLE_EQ(s.lightTolerance, 0.03);

  // The command line's over them; the scene's min_patch_size is taken against the command line's
  // patch size, at most that (a uniform mesh).
  SettingsOverrides cli;
  cli.patchSize = 0.01, cli.estimator = "pixels", cli.rotationSeed = 7, cli.backend = "embree";
  s = resolveSettings(d, cli);
  EXPECT_DOUBLE_EQ(s.patchSize, 0.01);
  EXPECT_DOUBLE_EQ(s.minPatchSize, 0.01);
  EXPECT_EQ(s.estimator, "pixels");
  EXPECT_EQ(s.rotationSeed, 7u);
  EXPECT_EQ(s.backend, "embree");
  EXPECT_EQ(s.window, "tetra");
  EXPECT_EQ(s.resolution, 128u);
  cli.minPatchSize = 0.004, cli.resolution = 64, cli.window = "hemicube";
  s = resolveSettings(d, cli);
  EXPECT_DOUBLE_EQ(s.minPatchSize, 0.004);
  EXPECT_EQ(s.resolution, 64u);
  EXPECT_EQ(s.window, "hemicube");

  // Resolved settings resolve to themselves (preprocessScene resolves a library caller's 0s again).
  FirstShotSettings again = s;
  resolvePatchSizes(d, again);
  EXPECT_EQ(again.hash(), s.hash());
  EXPECT_DOUBLE_EQ(resolvePatchSize(d), 0.2);

  cli.resolution = 33;
  EXPECT_THROW(resolveSettings(d, cli), InputError);  // the hemicube's side faces are R/2 high
}

// A library caller's automatic sizes (0) reach the table resolved, as the command line's do.
TEST(PreprocessSettings, TableHoldsTheResolvedSizes) {
  const SceneDesc d = test::sceneFromJson(R"({
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}]})");
  PreprocessOptions o = defaultOptions(d);
  o.settings.backend = "embree", o.settings.resolution = 16, o.threads = 1, o.quiet = true;
  const FirstShotTable resolved = preprocessScene(d, o);
  o.settings.patchSize = o.settings.minPatchSize = 0;
  const FirstShotTable automatic = preprocessScene(d, o);
  EXPECT_DOUBLE_EQ(automatic.settings.patchSize, autoPatchSize(d));
  EXPECT_DOUBLE_EQ(automatic.settings.minPatchSize, automatic.settings.patchSize / kDefaultRefineRatio);
  EXPECT_EQ(automatic.settings.hash(), resolved.settings.hash());
  EXPECT_EQ(automatic.factor, resolved.factor);
}

}  // namespace
}  // namespace firstshot
