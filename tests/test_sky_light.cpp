// The sky, the sun and environment maps as lights of the render scene (render/scene/sky_light.h): the
// baked map keeps each model's horizontal illuminance (0.5%); an upward sensor on an unobstructed plane reads the
// sky's horizontal illuminance plus the sun's (DF = 100%) within 3σ for the CIE overcast, CIE clear and Perez skies;
// NEE only, BSDF sampling only and their MIS agree within 3σ under a clear sky with an area light beside it; a
// constant environment map over a diffuse plane gives ρ·L and is the background; bad input exits 2 naming the key
// (the parser's own checks: tests/test_scene_sky.cpp).
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/lights/perez_sky.h"
#include "common/lights/photometry.h"
#include "common/lights/sun_position.h"
#include "common/scene/sky_desc.h"
#include "common/util/error.h"
#include "render/firstshot/lighting.h"
#include "render/lights/light_sampler.h"
#include "render/lights/next_event.h"
#include "render/output/image_io.h"
#include "render/scene/sky_light.h"
#include "render/sensors/sensors.h"
#include "render_util.h"
#include "test_util.h"

using namespace firstshot;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;

/// A 40 m square plane at y = 0 of albedo @p rho, a camera looking down at it, and the JSON members @p daylight.
std::string planeScene(const std::string& daylight, double rho = 0.5, const std::string& extraShapes = "") {
  return fmt::format(R"({{
    "camera": {{"position": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30, "resolution": [8, 8]}},
    "materials": {{"ground": {{"type": "diffuse", "albedo": {}}}, "lamp": {{"type": "diffuse", "albedo": 0, "emission": 2000}}}},
    "shapes": [{{"type": "quad", "material": "ground", "vertices": [[-20,0,-20],[-20,0,20],[20,0,20],[20,0,-20]]}}{}],
    {}}})", rho, extraShapes, daylight);
}

/// ∫ L cos θ dω of @p map over the upper hemisphere in lux: each texel's radiance times its exact ∫ cos θ dω.
double mapHorizontalLux(const EnvironmentMap& map) {
  const int w = map.width(), h = map.height();
  double sum = 0.0;
  for (int j = 0; j < h / 2; ++j) {
    const double t0 = kPi * j / h, t1 = kPi * (j + 1) / h, tc = 0.5 * (t0 + t1);
    const double cosSolidAngle = 0.5 * (std::cos(t0) * std::cos(t0) - std::cos(t1) * std::cos(t1)) * 2.0 * kPi / w;
    for (int i = 0; i < w; ++i) {
      const double phi = ((i + 0.5) / w - 0.5) * 2.0 * kPi;
      const Vec3 d(float(std::sin(tc) * std::sin(phi)), float(std::cos(tc)), float(-std::sin(tc) * std::cos(phi)));
      sum += photometry::luminance(map.radiance(d)) * cosSolidAngle;
    }
  }
  return sum * photometry::kEfficacy;
}

/// The JSON of the three skies, and the illuminance (lux) on an unobstructed horizontal plane, computed here.
struct SkyCase {
  std::string name, json;
  double expectedLux;
};

std::vector<SkyCase> skyCases() {
  std::vector<SkyCase> cases;
  cases.push_back({"overcast", R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 10000})", 10000.0});
  // Clear sky with a sun by direction: its dome gives 20000 lux, the sun 80000 lux normal at altitude asin(0.6/|d|).
  const Vec3d d(-0.5, -0.6, 0.3);
  cases.push_back({"clear",
                   R"("sky": {"type": "cie-clear", "horizontal_illuminance": 20000,
                              "sun": {"direction": [-0.5, -0.6, 0.3], "illuminance": 80000}})",
                   20000.0 + 80000.0 * 0.6 / glm::length(d)});
  // Perez: Paris at 14:00 CEST on 21 June 2026; dome and sun from the model, the sun placed by Meeus.
  CivilTime t;
  t.year = 2026, t.month = 6, t.day = 21, t.hour = 14, t.utcOffsetHours = 2;
  const Vec3d sun = sunDirection(sunPosition(t, 48.85, 2.35), Vec3d(0, 0, -1));
  PerezInput in;
  in.directNormal = 700, in.diffuseHorizontal = 120, in.dayOfYear = 172;
  const PerezSky p = makePerezSky(sun, in);
  cases.push_back({"perez",
                   R"("sky": {"type": "perez", "direct_normal_irradiance": 700, "diffuse_horizontal_irradiance": 120,
                              "sun": {"latitude": 48.85, "longitude": 2.35, "timezone": 2, "date": "2026-06-21",
                                      "time": "14:00"}})",
                   p.dome.horizontalIlluminance() + p.directNormalLux * sun.y});
  return cases;
}

}  // namespace

TEST(SkyLight, BakedMapKeepsHorizontalIlluminance) {
  for (const SkyCase& c : skyCases()) {
    SCOPED_TRACE(c.name);
    const SceneDesc desc = test::sceneFromJson(planeScene(c.json));
    ASSERT_TRUE(desc.sky);
    const EnvironmentMap map = bakeSky(*desc.sky);
    const double model = desc.sky->dome.horizontalIlluminance(), baked = mapHorizontalLux(map);
    fmt::print("{}: map {:.2f} lux, model {:.2f} lux ({:+.4f}%)\n", c.name, baked, model, 100 * (baked / model - 1));
    EXPECT_NEAR(baked / model, 1.0, 0.005);
    // Below the horizon: the ground's luminance ρ (E_sky + E_sun)/π, here with ρ = 0.2 and the sun's horizontal part.
    const double ground = 0.2 * (c.expectedLux) / kPi;
    EXPECT_NEAR(photometry::luminance(map.radiance(Vec3(0.1f, -0.99f, 0.0f))) * photometry::kEfficacy, ground,
                1e-5 * ground);
  }
}

TEST(SkyLight, UpwardSensorReadsHorizontalIlluminance) {
  for (const char* name : {"path", "irradiance-cache"})
  for (const SkyCase& c : skyCases()) {
    SCOPED_TRACE(std::string(name) + ": " + c.name);
    const RenderScene scene(test::sceneFromJson(planeScene(c.json)), 0);
    auto integrator = makeIntegrator(name, IntegratorOptions());
    SensorOptions so;
    so.samples = 1 << 15;
    const std::vector<Sensor> sensors = {{Vec3(0.3f, 0.0f, -0.2f), Vec3(0, 1, 0)}};
    preprocessSensors(*integrator, scene, sensors, so);
    const auto res = estimateSensors(*integrator, scene, sensors, so);
    // The map's discretisation, measured by quadrature, is allowed beside 3σ.
    const double bake = std::abs(mapHorizontalLux(*scene.lights().environment()) - scene.desc().sky->dome.horizontalIlluminance());
    fmt::print("{} {}: {:.1f} ± {:.1f} lux, expected {:.1f} (bake {:.2f})\n", name, c.name, res[0].lux,
               res[0].stderrLux, c.expectedLux, bake);
    EXPECT_GT(res[0].stderrLux, 0.0);
    EXPECT_LT(res[0].stderrLux, 0.01 * c.expectedLux);  // a sharp test
    EXPECT_LE(std::abs(res[0].lux - c.expectedLux), 3 * res[0].stderrLux + bake + 1e-5 * c.expectedLux);
  }
}

TEST(SkyLight, CameraSeesTheModelNotTheTexels) {
  // Looking 60° from the zenith through a 0.05° field of view at the overcast sky: L = Lz (1 + 2 cos 60°)/3 = 2Lz/3.
  // The baked map's texel there (rows of 1.4°, its centre 0.23° away) would be 0.35% off.
  SceneDesc desc = test::sceneFromJson(planeScene(R"("sky": {"type": "cie-overcast", "zenith_luminance": 5000})"));
  desc.camera.position = Vec3d(0, 1, 0);
  desc.camera.lookAt = Vec3d(0, 1.5, -std::sqrt(0.75));
  desc.camera.up = Vec3d(0, 1, 0);
  desc.camera.fovYDeg = 0.05;
  desc.camera.width = desc.camera.height = 1;
  const RenderScene scene(std::move(desc), 0);
  const test::RenderRun run = test::renderPath(scene, IntegratorOptions(), 16);
  const double expected = skyRadiance(5000.0 * 2.0 / 3.0);
  EXPECT_NEAR(run.film.mean(0, 0).y, expected, 2e-4 * expected);
}

namespace {

/// Reflected radiance at one point of a diffuse plane by NEE only, BSDF sampling only and their MIS (the one
/// estimator that needs nextEventEnvironmentPdf right): equal within 3σ.
void checkNeeBsdfAndMis(const RenderScene& scene, const LightSampler& lights) {
  const EnvironmentMap& env = *scene.lights().environment();
  Hit hit;
  ASSERT_TRUE(scene.intersect(Ray(Vec3(0.3f, 1.0f, 0.2f), Vec3(0, -1, 0)), hit));
  const Frame frame(hit.ng);
  const Vec3 woLocal = frame.toLocal(Vec3(0, 1, 0));
  const BSDF bsdf = scene.bsdfAt(hit);
  const Vec3 n = hit.ng;
  NeeRequest plain, mis;
  plain.kept = mis.kept = true;
  plain.mis = false;
  // BSDF sampling: the radiance met along a sampled direction, weighted by @p w(pdf of the direction, NEE's pdf).
  auto bsdfSample = [&](Sampler& s, bool weighted) {
    BSDFQuery q(woLocal);
    const Color f = bsdf.sample(q, s.next2D());
    if (!(q.pdf > 0.0f)) return Color(0.0f);
    const Vec3 wi = frame.toWorld(q.wi);
    Hit y;
    if (!scene.intersect(Ray(hit.spawnOrigin(wi), wi), y))
      return f * env.radiance(wi) * (weighted ? powerHeuristic(q.pdf, nextEventEnvironmentPdf(lights, mis, wi)) : 1.0f);
    if (y.onPatch()) return Color(0.0f);
    const Color Le = scene.lights().emitted(y, -wi);
    return f * Le * (weighted ? powerHeuristic(q.pdf, nextEventPdf(lights, hit.p, n, mis, y)) : 1.0f);
  };
  constexpr int kN = 400000;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int k = 0; k < kN; ++k) {
    uint64_t rays = 0;
    Sampler s(11, k, 0);
    double v[3];
    v[0] = photometry::luminance(nextEvent(lights, hit, frame, woLocal, bsdf, plain, s, rays));
    v[1] = photometry::luminance(bsdfSample(s, false));
    v[2] = photometry::luminance(nextEvent(lights, hit, frame, woLocal, bsdf, mis, s, rays) + bsdfSample(s, true));
    for (int e = 0; e < 3; ++e) sum[e] += v[e], sum2[e] += v[e] * v[e];
  }
  double mean[3], se[3];
  for (int e = 0; e < 3; ++e) {
    mean[e] = sum[e] / kN;
    se[e] = std::sqrt((sum2[e] / kN - mean[e] * mean[e]) / (kN - 1));
  }
  fmt::print("NEE {:.5f} ± {:.5f}, BSDF {:.5f} ± {:.5f}, MIS {:.5f} ± {:.5f}\n", mean[0], se[0], mean[1], se[1],
             mean[2], se[2]);
  EXPECT_LT(se[2], se[1]);  // MIS beats BSDF sampling under a non-uniform sky
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      EXPECT_LE(std::abs(mean[a] - mean[b]), 3 * std::hypot(se[a], se[b])) << a << " vs " << b;
  // The sky alone: ρ/π · E_h of the map; the lamp (50× the sky's radiance where it hides it) adds to it.
  const double skyOnly = 0.7 / kPi * mapHorizontalLux(env) / photometry::kEfficacy;
  EXPECT_GT(mean[2], skyOnly);
}

}  // namespace

TEST(SkyLight, NeeBsdfSamplingAndMisAgree) {
  // A clear sky (a bright circumsolar region) and an area light 3 m up beside it: the kept group chooses the sky
  // beside the tree; or every light is taken.
  const std::string lamp =
      R"(, {"type": "quad", "material": "lamp", "vertices": [[1,3,-1],[2,3,-1],[2,3,0],[1,3,0]]})";
  const RenderScene scene(test::sceneFromJson(planeScene(
                              R"("sky": {"type": "cie-clear", "horizontal_illuminance": 20000,
                                         "sun": {"direction": [-0.5, -0.6, 0.3], "illuminance": 0}})",
                              0.7, lamp)),
                          0);
  for (LightStrategy strategy : {LightStrategy::Tree, LightStrategy::All}) {
    SCOPED_TRACE(strategy == LightStrategy::Tree ? "light tree" : "every light");
    IntegratorOptions io;
    io.lightSampler = strategy;
    auto integrator = makeIntegrator("path", io);
    integrator->preprocess(scene);
    const LightSampler& lights = *integrator->lightSampler();
    ASSERT_GT(lights.environmentPmf(), 0.0f);
    if (strategy == LightStrategy::Tree) {
      ASSERT_LT(lights.environmentPmf(), 1.0f);  // shared with the tree
    }
    checkNeeBsdfAndMis(scene, lights);
  }
}

TEST(SkyLight, ConstantEnvironmentMapIsAFurnaceAndTheBackground) {
  const std::string dir = test::tempDir();
  const std::vector<float> half(16 * 8 * 3, 0.5f);
  image::writeExr(dir + "/const.exr", 16, 8, {"R", "G", "B"}, half.data());
  const std::string env = R"("environment": {"file": ")" + dir + R"(/const.exr", "scale": 2, "rotate": 30})";
  constexpr double kRho = 0.6, kL = 1.0;  // 0.5 × scale 2
  const RenderScene scene(test::sceneFromJson(planeScene(env, kRho)), 0);
  const test::RenderRun run = test::renderPath(scene, IntegratorOptions(), 256);
  for (int c = 0; c < 3; ++c) {
    double mean = 0, se = 0;
    test::imageMean(run.film, c, mean, se);
    fmt::print("channel {}: {:.5f} ± {:.5f}, expected {}\n", c, mean, se, kRho * kL);
    EXPECT_GT(se, 0.0);
    EXPECT_LE(std::abs(mean - kRho * kL), 3 * se + 1e-5);
  }
  // Looking up: every camera ray leaves the scene and sees L.
  SceneDesc up = test::sceneFromJson(planeScene(env, kRho));
  up.camera.lookAt = Vec3d(0, 5, 0);
  const RenderScene sky(std::move(up), 0);
  const test::RenderRun background = test::renderPath(sky, IntegratorOptions(), 4);
  double mean = 0, se = 0;
  test::imageMean(background.film, 1, mean, se);
  EXPECT_NEAR(mean, kL, 1e-6);
}

TEST(SkyLight, CommandLineExitsTwoNamingTheKey) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/garbage.exr", "not an image");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"("sky": {"type": "perez", "direct_normal_irradiance": -5, "diffuse_horizontal_irradiance": 100,
                  "sun": {"direction": [0, -1, 0]}})",
       "sky.direct_normal_irradiance"},
      {R"("sun": {"latitude": 45, "longitude": 7, "timezone": 1, "date": "2026-02-31", "time": "12:00", "irradiance": 1})",
       "sun.date"},
      {R"("environment": {"file": "garbage.exr"})", "environment.file"},
  };
  for (const auto& [daylight, key] : cases) {
    test::writeText(dir + "/scene.json", planeScene(daylight));
    const auto r = test::run(kRender + " " + dir + "/scene.json --spp 1 -q -o " + dir + "/out.exr");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(key), std::string::npos) << r.output;
  }
  // The integrators that do not meet the sky yet refuse it.
  test::writeText(dir + "/scene.json", planeScene(R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 1000})"));
  const auto r = test::run(kRender + " " + dir + "/scene.json --integrator bdpt --spp 1 -q -o " + dir + "/out.exr");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("does not support a sky/environment yet"), std::string::npos) << r.output;
}

// The irradiance cache takes the sky as direct light (NEE at every vertex, the background for the camera's rays): a
// 2 m box on a plane under the overcast sky, the camera seeing plane, box and sky, renders as the path tracer does
// (the cache's interpolation bias, measured 0.02–0.2% on this scene, allowed beside 3σ of the two means). Without the
// sky the cache's image mean would be the sky's pixels alone (−60% here).
TEST(SkyLight, IrradianceCacheAgreesWithPathTracing) {
  const std::string box = R"(, {"type": "box", "material": "ground", "min": [-1, 0, -1], "max": [1, 2, 1]})";
  SceneDesc desc = test::sceneFromJson(
      planeScene(R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 10000})", 0.5, box));
  desc.camera.position = Vec3d(4, 3, 5);
  desc.camera.lookAt = Vec3d(0, 1, 0);
  desc.camera.up = Vec3d(0, 1, 0);
  desc.camera.width = 32, desc.camera.height = 24;
  const RenderScene scene(std::move(desc), 0);
  double mean[2], se[2];
  const char* names[2] = {"path", "irradiance-cache"};
  for (int k = 0; k < 2; ++k) {
    auto integrator = makeIntegrator(names[k], IntegratorOptions());
    integrator->preprocess(scene);
    const test::RenderRun run = test::renderWith(*integrator, scene, 256);
    test::imageMean(run.film, 1, mean[k], se[k]);
    fmt::print("{}: {:.5f} ± {:.5f}\n", names[k], mean[k], se[k]);
  }
  EXPECT_GT(se[0], 0.0);
  EXPECT_LE(std::abs(mean[1] - mean[0]), 3 * std::hypot(se[0], se[1]) + 0.005 * mean[0]);
}
