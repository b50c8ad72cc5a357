// Illuminance at sensor points (render/sensors/sensors.h, firstshot-render --sensors/--grid): analytic
// point-light values, indirect light from a lit floor, a grid against a cosine-ray reference,
// thread independence, outputs and bad input.
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "common/formats/load_scene.h"
#include "common/lights/photometry.h"
#include "common/patches/patch_size.h"
#include "common/sampling/sampling.h"
#include "common/table/firstshot.h"
#include "render/sensors/sensors.h"
#include "render_util.h"
#include "test_util.h"

using namespace firstshot;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;
constexpr double kPower = 100.0;  // W, point light at (0, 1, 0)

/// A point light 1 m over a square floor [-s, s]² at y = 0 of albedo @p rho.
std::string pointOverFloor(double rho, double s) {
  return fmt::format(R"({{
    "camera": {{"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30, "resolution": [16, 16]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": {}}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-{s},0,-{s}],[-{s},0,{s}],[{s},0,{s}],[{s},0,-{s}]]}}],
    "lights": [{{"type": "point", "position": [0, 1, 0], "power": {}}}],
    "settings": {{"patch_size": 0.25}}}})", rho, kPower, fmt::arg("s", s));
}

/// Irradiance from the light on a plane facing up at @p p: Φh/(4π(h²+r²)^1.5).
double pointIrradiance(const Vec3d& p) {
  const double h = 1.0 - p.y, r2 = p.x * p.x + p.z * p.z;
  return kPower * h / (4 * kPi * std::pow(h * h + r2, 1.5));
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ss(line);
  for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
  return f;
}

/// Asserts E within 3 standard errors (plus float rounding, 1e-5 relative).
void expectNear(double E, double expected, double se, const std::string& what) {
  EXPECT_LE(std::abs(E - expected), 3 * se + 1e-5 * expected) << what << ": " << E << " vs " << expected << " ± " << se;
}

}  // namespace

TEST(Sensors, PointLightOverBlackFloorCli) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", pointOverFloor(0.0, 3.0));
  const std::vector<Vec3d> points = {{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0.5}, {0, 0.25, 0}, {2, 0.5, -1}};
  std::string text = "# x y z nx ny nz\n\n";
  for (const Vec3d& p : points) text += fmt::format("{} {} {} 0 2 0\n", p.x, p.y, p.z);  // normal normalised on reading
  test::writeText(dir + "/points.txt", text);
  const auto r = test::run(kRender + " " + dir + "/scene.json --sensors " + dir + "/points.txt --samples 16 -q -o " +
                           dir + "/out.csv -o " + dir + "/out.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("E_avg"), std::string::npos) << r.output;

  std::ifstream csv(dir + "/out.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "x,y,z,nx,ny,nz,irradiance_r,irradiance_g,irradiance_b,illuminance_lux,stderr_lux");
  for (const Vec3d& p : points) {
    ASSERT_TRUE(std::getline(csv, line));
    const auto f = splitCsv(line);
    ASSERT_EQ(f.size(), 11u) << line;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::stod(f[k]), p[k], 1e-6);
    EXPECT_EQ(std::stod(f[4]), 1.0);
    const double lux = std::stod(f[9]), se = std::stod(f[10]);
    const Color E(std::stof(f[6]), std::stof(f[7]), std::stof(f[8]));
    EXPECT_NEAR(lux, photometry::lux(E), 1e-6 * lux);
    EXPECT_NEAR(lux, 179.0 * E.x, 1e-5 * lux);  // white light: Y = R = G = B
    expectNear(E.x, pointIrradiance(p), se / 179.0, line);
  }
  EXPECT_FALSE(std::getline(csv, line));

  std::ifstream js(dir + "/out.json");
  const auto j = nlohmann::json::parse(js);
  ASSERT_EQ(j["sets"].size(), 1u);
  const auto& set = j["sets"][0];
  ASSERT_EQ(set["rows"].size(), points.size());
  double minLux = 1e30, sum = 0;
  for (const auto& row : set["rows"]) {
    minLux = std::min(minLux, row[9].get<double>());
    sum += row[9].get<double>();
  }
  EXPECT_NEAR(set["E_min"].get<double>(), minLux, 1e-6 * minLux);
  EXPECT_NEAR(set["E_avg"].get<double>(), sum / double(points.size()), 1e-6 * sum);
  EXPECT_NEAR(set["U0"].get<double>(), minLux / (sum / double(points.size())), 1e-6);
}

// A sensor 0.5 m over a lit floor of albedo 0.5, facing down, receives only the floor's reflected light:
// E = ∫ ρ/π E_floor(x') h²/d⁴ dA'. Facing up, it receives the point light's E. With a first-shot
// table (the light replaced) the sensor still samples the light exactly.
TEST(Sensors, IndirectFromLitFloor) {
  constexpr double kRho = 0.5, kHalf = 2.0, kH = 0.5;
  const Vec3d at(0.3, kH, 0.2);
  // The floor's reflected light at the sensor, midpoint rule over the square.
  double expectedDown = 0;
  const int n = 800;
  const double cell = 2 * kHalf / n;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      const Vec3d x(-kHalf + (i + 0.5) * cell, 0, -kHalf + (k + 0.5) * cell);
      const double d2 = glm::dot(x - at, x - at);
      expectedDown += kRho / kPi * pointIrradiance(x) * kH * kH / (d2 * d2) * cell * cell;
    }
  const SceneDesc desc = test::sceneFromJson(pointOverFloor(kRho, kHalf));
  for (bool table : {false, true}) {
    SCOPED_TRACE(table ? "with a first-shot table" : "without a table");
    PatchMesh mesh = buildPatches(desc, 0.25);
    const RenderScene scene = table ? RenderScene(desc, test::pointLightTable(desc, std::move(mesh), 0))
                                    : RenderScene(desc, 0.25);
    auto integrator = makeIntegrator("path", IntegratorOptions());
    integrator->preprocess(scene);
    SensorOptions so;
    so.samples = 4096;
    const std::vector<Sensor> sensors = {{Vec3(at), Vec3(0, -1, 0)}, {Vec3(at), Vec3(0, 1, 0)}};
    const auto res = estimateSensors(*integrator, scene, sensors, so);
    const double down = res[0].irradiance.x, seDown = res[0].stderrLux / 179.0;
    fmt::print("down: {:.6f} ± {:.6f}, expected {:.6f}\n", down, seDown, expectedDown);
    EXPECT_GT(seDown, 0.0);
    EXPECT_LT(seDown, 0.05 * expectedDown);  // a sharp test
    expectNear(down, expectedDown, seDown, "facing down");
    expectNear(res[1].irradiance.x, pointIrradiance(at), res[1].stderrLux / 179.0, "facing up");
  }
}

// Integrating sphere (tests/render_util.h) with the light replaced by an exact first-shot table: at a sensor
// on the wall, facing inwards, E − (the light's direct E) = ρΦ/(A(1−ρ)), A the tessellated area (uniform on the
// wall of a true sphere; not at interior points, which weight the unevenly lit wall differently).
TEST(Sensors, IntegratingSphereIndirect) {
  const double rho = 0.6, phi = 50.0;
  const SceneDesc desc = test::sceneFromJson(test::integratingSphereScene(rho, phi));
  PatchMesh mesh = buildPatches(desc, resolvePatchSize(desc));
  const double area = mesh.totalArea();
  std::vector<Sensor> sensors;
  for (size_t j = 0; j < mesh.patches.size(); j += mesh.patches.size() / 5) {
    const Patch& pj = mesh.patches[j];
    sensors.push_back({pj.centroid, glm::dot(pj.normal, pj.centroid) < 0 ? pj.normal : -pj.normal});
  }
  const RenderScene scene(desc, test::pointLightTable(desc, std::move(mesh), 0));
  ASSERT_NE(scene.firstShot(), nullptr);
  const double expected = rho * phi / (area * (1.0 - rho));
  IntegratorOptions io;
  io.maxDepth = 100000;  // Russian roulette ends the paths
  auto integrator = makeIntegrator("path", io);
  integrator->preprocess(scene);
  const Vec3d light(0.3, 0.25, -0.1);
  SensorOptions so;
  so.samples = 2048;
  const auto res = estimateSensors(*integrator, scene, sensors, so);
  double sum = 0, var = 0;
  for (size_t i = 0; i < sensors.size(); ++i) {
    const Vec3d d = light - Vec3d(sensors[i].p);
    const double cosine = std::max(0.0, glm::dot(glm::normalize(d), Vec3d(sensors[i].n)));
    const double direct = phi * cosine / (4 * kPi * glm::dot(d, d));
    const double indirect = res[i].irradiance.x - direct, se = res[i].stderrLux / 179.0;
    fmt::print("sensor {}: indirect {:.5f} ± {:.5f} (expected {:.5f})\n", i, indirect, se, expected);
    EXPECT_GT(se, 0.0);
    EXPECT_LE(std::abs(indirect - expected), 4 * se + 1e-5 * direct) << i;
    sum += indirect;
    var += se * se;
  }
  const double mean = sum / double(sensors.size()), seMean = std::sqrt(var) / double(sensors.size());
  EXPECT_LE(std::abs(mean - expected), 3 * seMean);
  EXPECT_LT(seMean, 0.02 * expected);  // sharp enough to catch a missing or doubled bounce
}

namespace {

/// The cornell-metre grid 4 m above the floor (over the blocks), 3 × 3 points.
struct CornellGrid {
  RenderScene scene{loadScene(test::source("scenes/cornell-metre.json"))};
  std::unique_ptr<Integrator> integrator = makeIntegrator("path", IntegratorOptions());
  SensorSet grid = parseGrid("0.5,0.5,5,5,4,1.5");
  CornellGrid() { integrator->preprocess(scene); }
};

}  // namespace

// E per point, E_avg and U0 against an independent estimate: π · Li along cosine-distributed rays
// (no NEE at the sensor; the light counted when a ray meets it), σ from the samples.
TEST(Sensors, CornellGridAgainstCosineRays) {
  CornellGrid c;
  ASSERT_EQ(c.grid.sensors.size(), 9u);
  SensorOptions so;
  so.samples = 1024;
  const auto res = estimateSensors(*c.integrator, c.scene, c.grid.sensors, so);
  const SensorSummary sum = summarize(res);

  std::vector<SensorResult> ref(res.size());
  constexpr int kRef = 4096;
  tbb::parallel_for(size_t(0), res.size(), [&](size_t i) {
    const Sensor& s = c.grid.sensors[i];
    const Frame frame(s.n);
    double m = 0, m2 = 0;
    for (int k = 0; k < kRef; ++k) {
      Sampler sampler(99, i, uint64_t(k), 1);
      const Vec3 wi = frame.toWorld(squareToCosineHemisphere(sampler.next2D()));
      const double lux = photometry::lux(kPiF * c.integrator->Li(Ray(s.p, wi), sampler));
      m += lux;
      m2 += lux * lux;
    }
    ref[i].lux = m / kRef;
    ref[i].stderrLux = std::sqrt(std::max(0.0, m2 / kRef - ref[i].lux * ref[i].lux) / (kRef - 1));
  });
  const SensorSummary refSum = summarize(ref);
  double var = 0;
  for (size_t i = 0; i < res.size(); ++i) {
    const double se = std::hypot(res[i].stderrLux, ref[i].stderrLux);
    EXPECT_LE(std::abs(res[i].lux - ref[i].lux), 4 * se) << i << ": " << res[i].lux << " vs " << ref[i].lux;
    EXPECT_LT(res[i].stderrLux, ref[i].stderrLux) << "NEE at the sensor should beat cosine rays alone";
    var += se * se;
  }
  const double seAvg = std::sqrt(var) / double(res.size());
  fmt::print("E_avg {:.3f} lx (ref {:.3f} ± {:.3f}), U0 {:.4f} (ref {:.4f})\n", sum.avgLux, refSum.avgLux, seAvg,
             sum.uniformity, refSum.uniformity);
  EXPECT_LE(std::abs(sum.avgLux - refSum.avgLux), 3 * seAvg);
  // U0 = E_min/E_avg: σ by the delta method from the minimum point's and the average's errors.
  const size_t iMin = size_t(std::min_element(ref.begin(), ref.end(), [](auto& a, auto& b) { return a.lux < b.lux; }) -
                             ref.begin());
  const double seMin = std::hypot(res[iMin].stderrLux, ref[iMin].stderrLux);
  const double seU0 = refSum.uniformity * std::hypot(seMin / refSum.minLux, seAvg / refSum.avgLux);
  EXPECT_LE(std::abs(sum.uniformity - refSum.uniformity), 4 * seU0);
  EXPECT_GT(sum.uniformity, 0.0);
  EXPECT_LT(sum.uniformity, 1.0);
}

TEST(Sensors, ThreadCountDoesNotChangeResults) {
  CornellGrid c;
  SensorOptions so;
  so.samples = 24;
  so.batch = 5;
  so.threads = 1;
  const auto one = estimateSensors(*c.integrator, c.scene, c.grid.sensors, so);
  so.threads = 2;
  const auto two = estimateSensors(*c.integrator, c.scene, c.grid.sensors, so);
  for (size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].lux, two[i].lux);
    EXPECT_EQ(one[i].stderrLux, two[i].stderrLux);
    EXPECT_EQ(one[i].irradiance, two[i].irradiance);
    EXPECT_EQ(one[i].samples, 24u);
  }
}

// The sensors' NEE takes the integrator's light sampler and first-shot lighting (Integrator::lightSampler), built
// once by its preprocessing: every integrator that supports the sensors has one, over every light and this scene;
// the others have none.
TEST(Sensors, ShareTheIntegratorsLightSampler) {
  const SceneDesc desc = test::sceneFromJson(pointOverFloor(0.5, 2.0));
  const RenderScene scene(desc, 0.25);
  for (const std::string& name : integratorNames()) {
    SCOPED_TRACE(name);
    auto integrator = makeIntegrator(name, IntegratorOptions());
    integrator->preprocess(scene);
    const LightSampler* lights = integrator->lightSampler();
    ASSERT_EQ(lights != nullptr, integrator->supportsSensors());
    if (!lights) continue;
    EXPECT_EQ(&lights->scene(), &scene);
    ASSERT_EQ(lights->included().size(), scene.lights().lights().size());
    for (uint8_t included : lights->included()) EXPECT_EQ(included, 1);
  }
}

TEST(Sensors, BadInputExits2) {
  const std::string dir = test::tempDir();
  const std::string scene = test::source("scenes/point-over-plane.json");
  const std::string out = dir + "/out.csv";
  test::writeText(dir + "/short.txt", "0 0 0 0 1 0\n# comment\n1 2 3 0 1\n");
  test::writeText(dir + "/zero.txt", "0 0 0 0 0 0\n");
  test::writeText(dir + "/nan.txt", "\n0 nan 0 0 1 0\n");
  test::writeText(dir + "/empty.txt", "# nothing\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--sensors " + dir + "/short.txt", "short.txt: line 3"},
      {"--sensors " + dir + "/zero.txt", "zero.txt: line 1"},
      {"--sensors " + dir + "/nan.txt", "nan.txt: line 2"},
      {"--sensors " + dir + "/empty.txt", "no sensors"},
      {"--sensors " + dir + "/missing.txt", "missing.txt"},
      {"--grid 0,0,1,1,0.75", "--grid"},
      {"--grid 1,0,0,1,0.75,0.25", "--grid"},
      {"--grid 0,0,1,1,0.75,0.25 --integrator light", "--integrator"},
      {"--grid 0,0,1,1,0.75,0.25 --integrator bundle", "path or irradiance-cache"},
      {"--grid-quad nothing,0,0.25", "no shape named \"nothing\""},
      {"--grid-quad floor,0", "NAME,offset,spacing"},
      {"--grid-quad floor,0,-1", "spacing must be positive"},
      {"--grid 0,0,1,1,0.75,0.25 --spp 4", "--spp"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = test::run(kRender + " " + scene + " " + args + " -q -o " + out);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << args;
  }
  const auto r = test::run(kRender + " " + scene + " --grid 0,0,1,1,0.75,0.25 -q -o " + dir + "/out.png");
  EXPECT_EQ(r.exitCode, 2) << r.output;
}

// --grid-quad: a 2 m × 1 m rectangle tilted to the normal (0, 0.6, 0.8), moved and turned by a transform,
// and its flipped twin. Cell centres bilinear in the corners, offset along the normal, the normal per sensor.
TEST(Sensors, GridOnNamedQuad) {
  const std::string quad = R"("vertices": [[0,0,0],[2,0,0],[2,0.8,-0.6],[0,0.8,-0.6]])";
  const SceneDesc desc = test::sceneFromJson(fmt::format(R"({{
    "materials": {{"m": {{"type": "diffuse", "albedo": 0.5}}}},
    "shapes": [{{"type": "quad", "name": "desk", "material": "m", {q}, "transform": {{"translate": [1, 2, 3]}}}},
               {{"type": "quad", "name": "under", "material": "m", {q}, "flip_normals": true}},
               {{"type": "box", "name": "crate", "material": "m", "min": [5, 5, 5], "max": [6, 6, 6]}},
               {{"type": "quad", "name": "twin", "material": "m", {q}}},
               {{"type": "quad", "name": "twin", "material": "m", {q}}}],
    "lights": [{{"type": "point", "position": [0, 5, 0], "power": 10}}]}})", fmt::arg("q", quad)));
  const Vec3d e1(2, 0, 0), e2(0, 0.8, -0.6), n(0, 0.6, 0.8);
  for (const auto& [spec, origin, normal] : {std::tuple{std::string("desk,0.1,0.5"), Vec3d(1, 2, 3), n},
                                             std::tuple{std::string("shapes[0],0.1,0.5"), Vec3d(1, 2, 3), n},
                                             std::tuple{std::string("under,-0.2,0.5"), Vec3d(0), -n}}) {
    SCOPED_TRACE(spec);
    const SensorSet set = gridOnQuad(desc, spec);
    ASSERT_EQ(set.sensors.size(), 8u);  // 2 m / 0.5 m × 1 m / 0.5 m
    const double offset = spec.starts_with("under") ? -0.2 : 0.1;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 4; ++i) {
        const Sensor& s = set.sensors[size_t(j * 4 + i)];
        // Flipped, the corners run the other way round: the same centres in another order.
        const double u = (i + 0.5) / 4, v = (j + 0.5) / 2;
        const Vec3d local = Vec3d(s.p) - origin - offset * normal;
        EXPECT_NEAR(glm::dot(local, normal), 0.0, 1e-6);  // in the quad's plane, offset along the normal
        const double a = glm::dot(local, e1) / 4.0, b = glm::dot(local, e2) / 1.0;  // e1·e1 = 4, e2·e2 = 1
        if (!spec.starts_with("under")) {
          EXPECT_NEAR(a, u, 1e-6);
          EXPECT_NEAR(b, v, 1e-6);
        }
        EXPECT_NEAR(a * 4 - 0.5, std::round(a * 4 - 0.5), 1e-5);  // a cell centre
        EXPECT_NEAR(b * 2 - 0.5, std::round(b * 2 - 0.5), 1e-5);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.n[k], normal[k], 1e-6);
      }
  }
  EXPECT_EQ(gridOnQuad(desc, "desk,0,0.3").sensors.size(), 7u * 3u);  // 2/0.3 → 7, 1/0.3 → 3
  for (const auto& [spec, message] : {std::pair{"crate,0,0.5", "not a quad"}, std::pair{"twin,0,0.5", "names both"},
                                      std::pair{"desk,0,0", "positive"}, std::pair{"desk,x,0.5", "NAME,offset,spacing"},
                                      std::pair{"nobody,0,0.5", "no shape named"}}) {
    try {
      gridOnQuad(desc, spec);
      ADD_FAILURE() << spec << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--grid-quad"), std::string::npos) << e.what();
    }
  }
}

// The CLI's --grid-quad on point-over-plane's floor: the rows are its cells, facing up.
TEST(Sensors, GridQuadCli) {
  const std::string dir = test::tempDir();
  const auto r = test::run(kRender + " " + test::source("scenes/point-over-plane.json") +
                           " --grid-quad floor,0.5,1 --grid 0,0,1,1,0.5,1 --samples 4 -q -o " + dir + "/out.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream js(dir + "/out.json");
  const auto j = nlohmann::json::parse(js);
  ASSERT_EQ(j["sets"].size(), 2u);
  EXPECT_EQ(j["sets"][1]["name"], "grid-quad floor,0.5,1");
  const SensorSet expected = gridOnQuad(loadScene(test::source("scenes/point-over-plane.json")), "floor,0.5,1");
  ASSERT_EQ(j["sets"][1]["rows"].size(), expected.sensors.size());
  for (size_t i = 0; i < expected.sensors.size(); ++i) {
    const auto& row = j["sets"][1]["rows"][i];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(row[k].get<double>(), expected.sensors[i].p[k], 1e-6);
    EXPECT_NEAR(row[4].get<double>(), 1.0, 1e-6);  // the floor faces up
  }
}

// A point light (100 W) in a clear glass ball (r = 10 cm) 2 m above a black floor: no shadow ray passes the glass and
// no ray meets a point light, so sensors that take the bulb as a light read 0 lx. Its luminaire's specular light (a
// point source at the ball's centre) gives the bare bulb's E = Φ/(4π)·cos θ/d² (a closed lossless shell lets all of
// it out radially). With a small emissive sphere at the centre instead (a filament), the light leaving the glass is
// isotropic by symmetry: E = Φ_s/(4π)·cos θ/d², Φ_s the table's specular power (what the glass and the filament, which
// absorbs what comes back to it, let out). Allowed: 1% beside 3 of the intensity bins' frozen noise, √(512/N) for N
// particles, and 3 σ.
TEST(Sensors, ABulbInAGlassBallThroughItsLuminaire) {
  const std::string dir = test::tempDir(), pre = FIRSTSHOT_PREPROCESS_EXE;
  const uint64_t particles = 1u << 20;
  for (const bool point : {true, false}) {
    const std::string scene = dir + (point ? "/point.json" : "/sphere.json"), fsd = scene + ".fsd";
    test::writeText(scene, fmt::format(R"({{"materials": {{"floor": {{"type": "diffuse", "albedo": 0}},
        "glass": {{"type": "dielectric", "ior": 1.5}}, "filament": {{"type": "diffuse", "emission": 200}}}},
      "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-10,0,-10],[-10,0,10],[10,0,10],[10,0,-10]]}},
                 {{"type": "sphere", "material": "glass", "center": [0, 2, 0], "radius": 0.1, "subdivisions": 4, "smooth": true}}{}],
      {}"camera": {{"position": [0, 1, 4], "look_at": [0, 0.5, 0], "fov_y": 50, "resolution": [16, 16]}},
      "settings": {{"patch_size": 2.0}}}})",
        point ? "" : R"(, {"type": "sphere", "material": "filament", "center": [0, 2, 0], "radius": 0.03, "subdivisions": 2})",
        point ? R"("lights": [{"type": "point", "position": [0, 2, 0], "power": 100}], )" : ""));
    const auto p = test::run(pre + " " + scene + " -o " + fsd + " --quiet --luminaire-particles " +
                             std::to_string(particles));
    ASSERT_EQ(p.exitCode, 0) << p.output;
    const std::vector<Vec3d> points = {{0, 0, 0}, {1, 0, 0}, {0.7, 0, 0.55}, {1.5, 0, -0.8}};
    std::string text;
    for (const Vec3d& q : points) text += fmt::format("{} {} {} 0 1 0\n", q.x, q.y, q.z);
    test::writeText(dir + "/points.txt", text);
    auto sensors = [&](const std::string& luminaires, int samples, const std::string& integrator = "path") {
      const auto r = test::run(kRender + " " + scene + " --firstshot " + fsd + " --luminaires " + luminaires +
                               " --integrator " + integrator + " --sensors " + dir + "/points.txt --samples " +
                               std::to_string(samples) + " -q -o " + dir + "/out.csv");
      EXPECT_EQ(r.exitCode, 0) << r.output;
      std::ifstream csv(dir + "/out.csv");
      std::string line;
      std::getline(csv, line);
      std::vector<std::pair<double, double>> e;  // irradiance (green) and its standard error, W/m²
      while (std::getline(csv, line)) {
        const auto f = splitCsv(line);
        e.emplace_back(std::stod(f[7]), std::stod(f[10]) / std::stod(f[9]) * std::stod(f[7]));
      }
      return e;
    };
    const auto on = sensors("on", 64);
    ASSERT_EQ(on.size(), points.size());
    const double frozen = std::sqrt(512.0 / double(particles));
    if (point) {
      // The irradiance cache takes the luminaire's light as direct light, as the path tracer's sensor vertex does.
      const auto cache = sensors("on", 64, "irradiance-cache");
      ASSERT_EQ(cache.size(), points.size());
      for (size_t i = 0; i < points.size(); ++i) {
        const double d2 = 4.0 + points[i].x * points[i].x + points[i].z * points[i].z;
        const double expected = 100.0 / (4.0 * kPi) * (2.0 / std::sqrt(d2)) / d2;
        EXPECT_NEAR(on[i].first, expected, (0.01 + 3.0 * frozen) * expected + 3.0 * on[i].second) << "sensor " << i;
        EXPECT_NEAR(cache[i].first, expected, (0.01 + 3.0 * frozen) * expected + 3.0 * cache[i].second)
            << "sensor " << i << ", irradiance cache";
      }
      const auto off = sensors("off", 64);
      for (const auto& [e, se] : off) EXPECT_EQ(e, 0.0) << "no ray finds a point light behind glass";
      // Not silently: the lights taken as lights (--luminaires off, --light-sampler all) are said on stderr.
      for (const char* how : {"--luminaires off", "--light-sampler all"}) {
        const auto r = test::run(kRender + " " + scene + " --firstshot " + fsd + " " + how + " --sensors " + dir +
                                 "/points.txt --samples 4 -q -o " + dir + "/warn.csv");
        EXPECT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("warning: the sensors take luminaire"), std::string::npos) << how << ": " << r.output;
      }
    } else {
      const FirstShotTable table = readFirstShot(fsd);
      ASSERT_EQ(table.luminaires.size(), 1u);
      const double power = table.luminaires[0].specularPower.y;
      EXPECT_GT(power, 0.8 * table.luminaires[0].power.y) << "most of the filament's light passes the glass";
      for (size_t i = 0; i < points.size(); ++i) {
        const double d2 = 4.0 + points[i].x * points[i].x + points[i].z * points[i].z;
        const double expected = power / (4.0 * kPi) * (2.0 / std::sqrt(d2)) / d2;
        EXPECT_NEAR(on[i].first, expected, (0.01 + 3.0 * frozen) * expected + 3.0 * on[i].second) << "sensor " << i;
      }
    }
  }
}
