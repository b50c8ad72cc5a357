// Direct light on a diffuse plane (albedo ρ), one bounce only: every pixel must show ρ/π·E(x)
// averaged over its footprint, with E analytic for a point, spot, directional and area light
// (NEE, and NEE+MIS for the area light), and with the first-shot term under --primary patch,
// evaluated per point (visible fraction × the exact unoccluded term), so that it is E(x) too.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/lights/spot_cone.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

constexpr double kRho = 0.5;
constexpr int kBlock = 8;  // pixels per side of the blocks tested one by one

/// The plane y = 0 (2 m × 2 m) seen from 3 m above, every pixel on the plane, plus @p lights and @p extraShapes.
std::string planeScene(const std::string& lights, const std::string& extraMaterials = "", const std::string& extraShapes = "",
                       double patchSize = 0.1) {
  return fmt::format(R"({{
    "camera": {{"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30, "resolution": [32, 32]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": {}}}{}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}}{}],
    "lights": [{}],
    "settings": {{"patch_size": {}}}}})", kRho, extraMaterials, extraShapes, lights, patchSize);
}

/// The point where a camera ray meets the plane y = 0.
Vec3d onPlane(const Ray& r) {
  const double t = -double(r.o.y) / double(r.d.y);
  return Vec3d(r.o) + t * Vec3d(r.d);
}

/// Expected pixel values: footprint averages of ρ/π·E(x).
std::vector<double> expectedImage(const Camera& camera, const std::function<double(const Vec3d&)>& irradiance) {
  std::vector<double> e(size_t(camera.width()) * camera.height());
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x)
      e[size_t(y) * camera.width() + x] =
          test::footprintAverage(camera, x, y, [&](const Ray& r) { return kRho / kPi * irradiance(onPlane(r)); });
  return e;
}

/// Asserts the whole image within 3 standard errors and every block within 4 (plus @p slack per pixel,
/// and float rounding, 1e-5 relative).
void expectMatches(const Film& film, const std::vector<double>& expected, double slack, const std::string& what) {
  double meanExpected = 0;
  for (double e : expected) meanExpected += e / double(expected.size());
  const test::Comparison c = test::compareImage(film, expected, 0, kBlock, slack + 1e-5 * meanExpected);
  fmt::print("{:>28}: mean {:.6f}, expected {:.6f}, diff {:+.2e} ± {:.2e}, worst block z {:.2f}, max |pixel diff| {:.2e}\n",
             what, c.meanExpected + c.meanDiff, c.meanExpected, c.meanDiff, c.se, c.worstBlockZ, c.maxAbsDiff);
  EXPECT_GT(c.meanExpected, 0.0);
  EXPECT_LE(std::abs(c.meanDiff), 3 * c.se + slack + 1e-5 * c.meanExpected) << what;
  EXPECT_LE(c.worstBlockZ, 4.0) << what;
}

IntegratorOptions directOnly(PrimaryMode mode = PrimaryMode::Exact) {
  IntegratorOptions io;
  io.maxDepth = 1;
  io.primary = mode;
  return io;
}

const Vec3d kUp(0, 1, 0);

}  // namespace

TEST(DirectLight, PointLightOverPlane) {
  const SceneDesc desc = test::sceneFromJson(planeScene(R"({"type": "point", "position": [0.2, 1, 0.1], "power": 100})"));
  const RenderScene scene(desc);
  const auto run = test::renderPath(scene, directOnly(), 16);
  const Vec3d light = desc.lights[0].position;
  expectMatches(run.film, expectedImage(Camera(desc.camera), [&](const Vec3d& x) {
    const Vec3d d = light - x;
    return 100.0 / (4 * kPi) * glm::dot(d, kUp) / std::pow(glm::dot(d, d), 1.5);  // Φ h / (4π r³)
  }), 0, "point, NEE");
}

TEST(DirectLight, SpotLightOverPlane) {
  const SceneDesc desc = test::sceneFromJson(planeScene(
      R"({"type": "spot", "position": [0, 1, 0], "direction": [0.3, -1, 0], "inner_angle": 15, "outer_angle": 30, "power": 100})"));
  const LightDesc& spot = desc.lights[0];
  // The profile's normalisation: ∫ I dω = Φ (midpoint rule in θ).
  double power = 0;
  const int steps = 200000;
  for (int i = 0; i < steps; ++i) {
    const double theta = (i + 0.5) * kPi / steps;
    power += 2 * kPi * spotIntensity0(spot).x * spotProfile(spot, float(std::cos(theta))) * std::sin(theta) * kPi / steps;
  }
  EXPECT_NEAR(power, 100.0, 1e-3);
  const RenderScene scene(desc);
  const auto run = test::renderPath(scene, directOnly(), 16);
  expectMatches(run.film, expectedImage(Camera(desc.camera), [&](const Vec3d& x) {
    const Vec3d d = x - spot.position;
    const double r = glm::length(d);
    return double(spotIntensity(spot, Vec3(d / r)).x) * glm::dot(-d, kUp) / (r * r * r);
  }), 0, "spot, NEE");
}

TEST(DirectLight, DirectionalLightOverPlane) {
  const SceneDesc desc = test::sceneFromJson(planeScene(R"({"type": "directional", "direction": [0.3, -1, 0.2], "irradiance": 3})"));
  const RenderScene scene(desc);
  const auto run = test::renderPath(scene, directOnly(), 4);
  const Vec3d dir = desc.lights[0].direction;  // normalised by validation
  expectMatches(run.film, expectedImage(Camera(desc.camera), [&](const Vec3d&) { return 3.0 * glm::dot(-dir, kUp); }), 0,
                "directional, NEE");
}

TEST(DirectLight, AreaLightOverPlane) {
  // A 0.3 m × 0.4 m emitter facing down, outside the camera's view: E(x) = π·Le·F(x).
  const SceneDesc desc = test::sceneFromJson(planeScene("", R"(, "lamp": {"type": "diffuse", "emission": 4})",
      R"(, {"type": "quad", "material": "lamp", "vertices": [[0.7,0.5,-0.2],[1.0,0.5,-0.2],[1.0,0.5,0.2],[0.7,0.5,0.2]]})"));
  ASSERT_EQ(desc.lights.size(), 1u);
  const RenderScene scene(desc);
  const auto run = test::renderPath(scene, directOnly(), 64);
  const std::vector<Vec3d> lamp = {{0.7, 0.5, -0.2}, {1.0, 0.5, -0.2}, {1.0, 0.5, 0.2}, {0.7, 0.5, 0.2}};
  expectMatches(run.film, expectedImage(Camera(desc.camera), [&](const Vec3d& x) {
    return kPi * 4.0 * analytic::pointPolygonFormFactor(x, kUp, lamp);
  }), 0, "area, NEE + MIS");
}

/// The point light replaced by an exact first-shot table (r_j = Ω_j/(4π A_j)), first-shot at the
/// camera hit: the term is evaluated per point (visible fraction × the exact unoccluded
/// irradiance at the hit, render/firstshot/lighting.h), so each pixel is the analytic ρ/π·E(x) over its
/// footprint whatever the patch size, with no patch-scale bias left (patch-averaged irradiance
/// used to be off by up to ρ/π·|∇E|max·diam(patch)).
TEST(DirectLight, PointLightFirstShotPatchMode) {
  const double phi = 100;
  for (double patchSize : {0.1, 0.02}) {
    SCOPED_TRACE(patchSize);
    const SceneDesc desc = test::sceneFromJson(planeScene(
        R"({"type": "point", "position": [0.2, 1, 0.1], "power": 100})", "", "", patchSize));
    PatchMesh mesh = buildPatches(desc, patchSize);
    const RenderScene scene(desc, test::pointLightTable(desc, std::move(mesh), 0));
    ASSERT_NE(scene.firstShot(), nullptr);
    const auto run = test::renderPath(scene, directOnly(PrimaryMode::Patch), 16);
    EXPECT_EQ(run.stats.nonFinite, 0u);
    const Camera camera(desc.camera);
    const Vec3d light = desc.lights[0].position;
    const std::vector<double> analytic = expectedImage(camera, [&](const Vec3d& x) {
      const Vec3d d = light - x;
      return phi / (4 * kPi) * glm::dot(d, kUp) / std::pow(glm::dot(d, d), 1.5);
    });
    expectMatches(run.film, analytic, 0.0, fmt::format("first-shot {} m, vs E(x)", patchSize));
  }
}
