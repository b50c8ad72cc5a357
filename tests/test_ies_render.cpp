// IES lights in the renderer and the preprocessor: illuminance at sensors against the table's
// intensities, the first-shot term against the exact per-point value and NEE, light tracing and
// BDPT against path tracing (which checks the sampled direction pdf), and malformed files through
// both tools (exit code 2, file and line named).
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/formats/load_scene.h"
#include "common/lights/ies.h"
#include "common/lights/photometry.h"
#include "common/sampling/rng.h"
#include "preprocess/preprocessor.h"
#include "render/firstshot/lighting.h"
#include "render/sensors/sensors.h"
#include "tests/bias_util.h"
#include "tests/block_compare.h"
#include "tests/ies_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

constexpr double kDeg = kPi / 180.0;
const std::string kRender = FIRSTSHOT_RENDER_EXE;
const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;

/// An IES light at (0, 1, 0) over a black floor 5 m below.
std::string overBlackFloor(const std::string& file, const std::string& extra = "") {
  return R"({"materials": {"black": {"type": "diffuse", "albedo": 0}},
    "shapes": [{"type": "quad", "material": "black", "vertices": [[-20,-4,-20],[-20,-4,20],[20,-4,20],[20,-4,-20]]}],
    "lights": [{"type": "ies", "position": [0, 1, 0], "file": ")" + file + "\"" + extra + R"(}],
    "settings": {"patch_size": 5}})";
}

/// A table brighter in the C0 plane than in C90 (quadrant symmetry; one value at the nadir), lower hemisphere only.
std::string asymmetricDownlight() {
  return test::iesText(1, test::angleRange(0, 90, 5), {0, 45, 90}, [](double v, double h) {
    const double s = std::sin(v * kDeg);
    return (1250 + 750 * std::cos(2 * h * kDeg) * s * s) * std::pow(std::cos(v * kDeg), 0.7);
  });
}

/// Sensors at distance 2 around (0, 1, 0) facing up, at polar angles V from the downward axis, and
/// their lux from candela function @p I(V, C): E = I cos V / r² (C from +x towards −z).
void expectSensorLux(const SceneDesc& desc, const std::function<double(double, double)>& I, double interpolation) {
  const RenderScene scene(desc, desc.settings.patchSize);
  auto integrator = makeIntegrator("path", IntegratorOptions());
  integrator->preprocess(scene);
  std::vector<Sensor> sensors;
  std::vector<double> expected;
  for (double v : {0.0, 20.0, 45.0, 70.0, 85.0})
    for (double c : {0.0, 30.0, 90.0, 200.0}) {
      if (v == 0 && c != 0) continue;  // the nadir has no C angle (the renderer reads C = 0 there)
      const Vec3d w(std::sin(v * kDeg) * std::cos(c * kDeg), -std::cos(v * kDeg), -std::sin(v * kDeg) * std::sin(c * kDeg));
      sensors.push_back({Vec3(Vec3d(0, 1, 0) + 2.0 * w), Vec3(0, 1, 0)});
      expected.push_back(I(v, c) * std::cos(v * kDeg) / 4.0);
    }
  SensorOptions so;
  so.samples = 16;
  const auto res = estimateSensors(*integrator, scene, sensors, so);
  for (size_t k = 0; k < sensors.size(); ++k) {
    const double tol = 3 * res[k].stderrLux + interpolation * expected[k] + 1e-5;
    EXPECT_LE(std::abs(res[k].lux - expected[k]), tol) << k << ": " << res[k].lux << " vs " << expected[k];
  }
}

}  // namespace

// 1000 cd in every direction, and I = 1000 cos V below the luminaire: lux = I cos θ / r² at sensors around it.
TEST(IesRender, SensorsSeeTheTablesIntensities) {
  const std::string constant = test::writeIes("const.ies", test::iesText(1, {0, 90, 180}, {0}, [](double, double) { return 1000.0; }));
  expectSensorLux(test::sceneFromJson(overBlackFloor(constant)), [](double, double) { return 1000.0; }, 1e-5);
  const std::string cosine = test::writeIes(
      "cos.ies", test::iesText(1, test::angleRange(0, 90, 2.5), {0}, [](double v, double) { return 1000 * std::cos(v * kDeg); }));
  expectSensorLux(test::sceneFromJson(overBlackFloor(cosine)), [](double v, double) { return 1000 * std::cos(v * kDeg); }, 3e-4);
  // The asymmetric table, and the same turned by 90° about the axis (C0 = −z): C ↦ C − 90.
  const std::string asym = test::writeIes("asym.ies", asymmetricDownlight());
  const IesData table = parseIes(asymmetricDownlight(), "asym.ies");
  expectSensorLux(test::sceneFromJson(overBlackFloor(asym)), [&](double v, double c) { return table.value(v, c); }, 1e-5);
  expectSensorLux(test::sceneFromJson(overBlackFloor(asym, R"(, "ies_reference": [0, 0, -1])")),
                  [&](double v, double c) { return table.value(v, c - 90); }, 1e-5);
}

// The first-shot term of an IES light over a floor of 0.2 m patches follows the table per point (as for spots).
TEST(IesRender, FirstShotFollowsTheTablePerPoint) {
  const std::string file = test::writeIes("asym.ies", asymmetricDownlight());
  const SceneDesc desc = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-1.5,0,-1.5],[-1.5,0,1.5],[1.5,0,1.5],[1.5,0,-1.5]]}],
    "lights": [{"type": "ies", "position": [0.05, 0.8, 0.02], "direction": [0.2, -1, 0], "lumens": 2000, "small": true,
                "file": ")" + file + R"("}], "settings": {"patch_size": 0.2}})");
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene scene(desc, preprocessScene(desc, po));
  ASSERT_EQ(scene.firstShot()->samples.size(), 1u);
  FirstShotLighting fsl;
  fsl.build(scene);
  const LightSample& ls = scene.firstShot()->samples[0];
  double err2 = 0, ref2 = 0;
  for (int m = 0; m < 5000; ++m) {
    Sampler sm(23, 0, m);
    const Vec2 u = sm.next2D();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray(Vec3(-1.2f + 2.4f * u.x, 1.0f, -1.2f + 2.4f * u.y), Vec3(0, -1, 0)), hit));
    const double exact = test::unoccludedSampleIrradiance(ls, hit.p, Vec3(0, 1, 0), &desc.lights[0]).x;
    const double got = fsl.irradiance(hit, hit.ng.y > 0.0f).x;
    err2 += (got - exact) * (got - exact), ref2 += exact * exact;
  }
  fmt::print("IES over a floor: per-point first-shot irradiance rel. L2 error {:.2e}\n", std::sqrt(err2 / ref2));
  EXPECT_GT(ref2, 0.0);
  EXPECT_LT(std::sqrt(err2 / ref2), 0.01);
}

namespace {

/// The room with a tilted asymmetric IES light (upward light as well: a second lobe).
SceneDesc iesRoomScene(const std::string& file, const std::string& extra = "") {
  return test::sceneFromJson(test::iesRoom(
      R"({"type": "ies", "position": [1.2, 1.3, 1.0], "direction": [0.3, -1, 0.2], "ies_reference": [0, 0, 1],
          "lumens": 1500, "file": ")" + file + "\"" + extra + "}"));
}

std::string roomTable() {
  return test::iesText(1, test::angleRange(0, 180, 10), test::angleRange(0, 180, 30), [](double v, double h) {
    const double down = v < 90 ? (1000 + 600 * std::cos(h * kDeg)) * std::cos(v * kDeg) : 0.0;
    return down + 200 * std::pow(std::sin(v * kDeg / 2), 4);
  });
}

}  // namespace

// First-shot (the IES light replaced by the table, Embree R = 64) against NEE path tracing: same blocks.
TEST(IesRender, FirstShotAgreesWithNee) {
  SceneDesc d = iesRoomScene(test::writeIes("room.ies", roomTable()), R"(, "small": true)");
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene plain(d, d.settings.patchSize), withTable(d, preprocessScene(d, po));
  ASSERT_FALSE(withTable.firstShot()->replacedLights.empty());
  IntegratorOptions io;
  io.maxDepth = d.settings.maxDepth;
  auto a = makeIntegrator("path", io), b = makeIntegrator("path", io);
  a->preprocess(withTable);
  b->preprocess(plain);
  test::expectBlocksAgree("IES room: first-shot vs NEE", test::blockMeans(*a, withTable, 200, 2), test::blockMeans(*b, plain, 200));
}

// Light tracing and BDPT emit from the table's sampled distribution: their images agree with path tracing
// (a type C table, and for light tracing also a type B floodlight aimed down at the box).
TEST(IesRender, LightTracingAgreesWithPathTracing) {
  test::expectAgreesWithPathTracing("light", "IES room", iesRoomScene(test::writeIes("room.ies", roomTable())), 400, 200);
  const std::string flood = test::writeIes("flood.ies", test::iesText(2, test::angleRange(-90, 90, 15), test::angleRange(0, 90, 15),
                                                                      [](double v, double h) {
                                                                        return 800 * std::pow(std::cos(v * kDeg) * std::cos(h * kDeg), 3) + 20;
                                                                      }));
  test::expectAgreesWithPathTracing("light", "IES room, type B", iesRoomScene(flood), 400, 200);
}
TEST(IesRender, BdptAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("IesRender.LightTracingAgreesWithPathTracing (the same emission sampling) and BdptHiddenLights.*");
  test::expectAgreesWithPathTracing("bdpt", "IES room", iesRoomScene(test::writeIes("room.ies", roomTable())), 150, 200);
}

// Malformed or unsupported files: both tools exit with code 2 and name the file and the line.
TEST(IesRender, MalformedFilesExitWithCode2) {
  const std::string good = test::iesText(1, {0, 45, 90}, {0}, [](double, double) { return 100.0; });
  const std::string header = "IESNA:LM-63-2002\n[TEST] x\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n";
  struct Case {
    std::string name, text, expect;
  };
  const std::vector<Case> cases = {
      {"truncated", good.substr(0, good.size() - 8), "line "},
      {"bad count", "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2.5 1 1 2 0 0 0\n1 1 10\n0 90\n0\n1 1\n", "line 3"},
      {"too many values", header + "0 45 90\n0\n1 2 3 4\n", "line 8"},
      {"non-monotonic", header + "0 50 45\n0\n1 2 3\n", "line 6"},
      {"nan", header + "0 45 90\n0\n1 nan 3\n", "line 8"},
      {"negative", header + "0 45 90\n0\n1 -2 3\n", "line 8"},
      {"tilt include", "IESNA:LM-63-2002\nTILT=INCLUDE\n1\n", "line 2"},
      {"no tilt", "IESNA:LM-63-2002\n[TEST] x\n", "TILT"},
      {"bad type", "TILT=NONE\n1 -1 1 3 1 4 2 0 0 0\n1 1 10\n0 45 90\n0\n1 2 3\n", "line 2"}};
  const std::string dir = test::tempDir();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string ies = dir + "/" + std::to_string(&c - cases.data()) + ".ies";
    test::writeText(ies, c.text);
    test::writeText(dir + "/scene.json", overBlackFloor(ies));
    try {  // every case through loadScene, as both tools load the scene
      loadScene(dir + "/scene.json");
      ADD_FAILURE() << "loaded";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), ies);
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
    }
    std::vector<std::string> commands;  // a few through the tools themselves (process start-up dominates)
    if (c.name == "truncated" || c.name == "bad count" || c.name == "non-monotonic" || c.name == "nan")
      commands.push_back(kRender + " " + dir + "/scene.json --spp 1 -q -o " + dir + "/x.exr");
    if (c.name == "truncated" || c.name == "tilt include") commands.push_back(kPreprocess + " " + dir + "/scene.json -q -o " + dir + "/x.fsd");
    for (const std::string& cmd : commands) {
      const auto r = test::run(cmd);
      EXPECT_EQ(r.exitCode, kExitBadInput) << cmd << "\n" << r.output;
      EXPECT_NE(r.output.find(ies), std::string::npos) << r.output;
      EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    }
  }
  test::writeText(dir + "/scene.json", overBlackFloor(dir + "/missing.ies"));
  const auto r = test::run(kRender + " " + dir + "/scene.json --spp 1 -q -o " + dir + "/x.exr");
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_NE(r.output.find("missing.ies"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.exr"));
}
