// The daylight factor at sensors (render/sensors/daylight_factor.h, firstshot-render --daylight-factor):
// E_outside's closed form 7π/9 · Lz against a numerical integral of the CIE overcast distribution; an unobstructed
// sensor reads DF = 100% within 3σ with the sun and a lamp switched off; a sensor in a closed box with lights inside
// reads 0; a sensor under a square roof opening of a black room matches a numerical integral over the opening within
// 3σ; the CLI's columns, summary, JSON and DF picture; bad input exits 2 naming the file and the key; and in
// scenes/daylit-office.json first-shot agrees with NEE.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/scene/sky_desc.h"
#include "common/util/error.h"
#include "preprocess/preprocessor.h"
#include "render/output/falsecolor.h"
#include "render/output/film.h"
#include "render/sensors/daylight_factor.h"
#include "render/sensors/sensors.h"
#include "render_util.h"
#include "shipped_first_shot.h"
#include "test_util.h"

using namespace firstshot;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;
constexpr const char* kOvercast = R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 10000})";

/// A 40 m ground at y = 0 (albedo 0.5), the JSON members @p daylight, and the extra shapes and lights given.
std::string groundScene(const std::string& daylight, const std::string& shapes = "", const std::string& lights = "") {
  return fmt::format(R"({{
    "camera": {{"position": [0, 2, 3], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [8, 8]}},
    "materials": {{"ground": {{"type": "diffuse", "albedo": 0.5}}, "black": {{"type": "diffuse", "albedo": 0}},
                  "lamp": {{"type": "diffuse", "albedo": 0.5, "emission": 500}}}},
    "shapes": [{{"type": "quad", "name": "ground", "material": "ground",
                "vertices": [[-20,0,-20],[-20,0,20],[20,0,20],[20,0,-20]]}}{}],
    "lights": [{}],
    {}}})", shapes, lights, daylight);
}

/// A sun, a point light and an emissive panel (on the ground, facing up, so that it hides no sky from a sensor at
/// y ≥ 0): the sun and the point light 2 m up would add to an upward sensor's illuminance if they were on.
const std::string kSunAndLamps = R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 10000,
                                             "sun": {"direction": [0.3, -0.8, 0.2], "illuminance": 80000}})";
const std::string kLampShape =
    R"(, {"type": "quad", "name": "panel", "material": "lamp",
          "vertices": [[2,0.001,-1],[2,0.001,1],[3,0.001,1],[3,0.001,-1]]})";
const std::string kPointLight = R"({"name": "bulb", "type": "point", "position": [1, 2, 0], "power": 500})";

/// One sensor's DF (percent) and its standard error, estimated by the path tracer in @p desc's daylight-factor scene.
struct DfSample {
  double df = 0, stderrDf = 0, outsideLux = 0;
  std::vector<std::string> off;
};
DfSample estimateDf(SceneDesc desc, const Sensor& sensor, int samples) {
  const DaylightFactorSetup setup = daylightFactorScene(desc);
  const RenderScene scene(std::move(desc), 0);
  auto integrator = makeIntegrator("path", IntegratorOptions());
  integrator->preprocess(scene);
  SensorOptions so;
  so.samples = samples;
  const auto r = estimateSensors(*integrator, scene, {sensor}, so);
  return {daylightFactorPercent(r[0].lux, setup.outsideLux), daylightFactorPercent(r[0].stderrLux, setup.outsideLux),
          setup.outsideLux, setup.switchedOff};
}

/// The CIE overcast sky's E_h (lux) by the midpoint rule in θ and φ (4000 × 64 cells) over
/// the model's own luminance: independent of the closed form and of the model's quadrature in cos θ.
double numericalOutsideLux(const SkyLuminance& sky) {
  constexpr int kTheta = 4000, kPhi = 64;
  double sum = 0.0;
  for (int i = 0; i < kTheta; ++i) {
    const double t = 0.5 * kPi * (i + 0.5) / kTheta;
    for (int j = 0; j < kPhi; ++j) {
      const double p = 2.0 * kPi * (j + 0.5) / kPhi;
      const Vec3d d(std::sin(t) * std::cos(p), std::cos(t), std::sin(t) * std::sin(p));
      sum += sky.luminance(d) * std::cos(t) * std::sin(t);
    }
  }
  return sum * (0.5 * kPi / kTheta) * (2.0 * kPi / kPhi);
}

}  // namespace

TEST(DaylightFactor, OutsideIlluminanceIsSevenNinthsPiZenithLuminance) {
  // Scaled by the zenith luminance: E_outside from the scene equals 7π/9 · Lz and the numerical integral.
  SceneDesc desc = test::sceneFromJson(groundScene(R"("sky": {"type": "cie-overcast", "zenith_luminance": 4000})"));
  const double numerical = numericalOutsideLux(desc.sky->dome);
  const DaylightFactorSetup setup = daylightFactorScene(desc);
  fmt::print("E_outside {:.4f} lx, 7π/9 Lz {:.4f} lx, numerical {:.4f} lx\n", setup.outsideLux, 7 * kPi / 9 * 4000,
             numerical);
  EXPECT_NEAR(setup.outsideLux, 7.0 * kPi / 9.0 * 4000.0, 1e-9 * setup.outsideLux);
  EXPECT_NEAR(numerical, setup.outsideLux, 1e-6 * setup.outsideLux);
  EXPECT_NEAR(desc.sky->dome.zenithLuminance(), 4000.0, 1e-9 * 4000.0);
}

TEST(DaylightFactor, SummaryAndMedian) {
  std::vector<SensorResult> r(4);
  for (int i = 0; i < 4; ++i) r[size_t(i)].lux = 100.0 * (i == 2 ? 9 : i + 1);  // 100, 200, 900, 400 lux
  const DaylightFactorSummary s = summarizeDaylightFactor(r, 10000.0);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 9.0);
  EXPECT_DOUBLE_EQ(s.avg, 4.0);
  EXPECT_DOUBLE_EQ(s.median, 3.0);  // (2 + 4)/2
  r.pop_back();
  EXPECT_DOUBLE_EQ(summarizeDaylightFactor(r, 10000.0).median, 2.0);
}

TEST(DaylightFactor, UnobstructedSensorIsOneHundredPercent) {
  // The sun (80 klx), a 500 W bulb and an emissive panel beside the sensor are switched off: DF = 100% within 3σ
  // (switched on, the sun alone would add ~ 600%).
  const SceneDesc desc = test::sceneFromJson(groundScene(kSunAndLamps, kLampShape, kPointLight));
  const DfSample s = estimateDf(desc, {Vec3(0.0f, 0.0f, 0.0f), Vec3(0, 1, 0)}, 1 << 15);
  fmt::print("unobstructed: DF {:.3f}% ± {:.3f}%\n", s.df, s.stderrDf);
  EXPECT_EQ(s.outsideLux, 10000.0);
  EXPECT_EQ(s.off, (std::vector<std::string>{"lights[0] (\"bulb\")", "sky.sun", "material lamp"}));
  EXPECT_GT(s.stderrDf, 0.0);
  EXPECT_LT(s.stderrDf, 1.0);  // a sharp test
  EXPECT_LE(std::abs(s.df - 100.0), 3 * s.stderrDf + 0.5);  // + the baked map's 0.5% (tests/test_sky_light.cpp)
}

TEST(DaylightFactor, ClosedBoxIsZero) {
  // A 2 m box around the sensor with a bulb and an emissive panel inside: switched off, nothing reaches it.
  const std::string box = R"(, {"type": "box", "material": "ground", "min": [-1, 0.01, -1], "max": [1, 2, 1]},
    {"type": "quad", "material": "lamp", "vertices": [[0.5,1.5,-0.3],[0.5,1.5,0.3],[0.5,1.9,0.3],[0.5,1.9,-0.3]]})";
  const std::string bulb = R"({"type": "point", "position": [0.5, 1.8, 0], "power": 100})";
  const SceneDesc desc = test::sceneFromJson(groundScene(kOvercast, box, bulb));
  const DfSample s = estimateDf(desc, {Vec3(0.0f, 1.0f, 0.0f), Vec3(0, 1, 0)}, 1024);
  EXPECT_EQ(s.df, 0.0);
  EXPECT_EQ(s.stderrDf, 0.0);
}

TEST(DaylightFactor, SensorUnderSquareOpening) {
  // A black room 8 × 8 m, 2 m high, with a 2 × 2 m opening in the middle of its roof; the sensor at the floor's
  // centre faces up. DF = ∫ L(θ) cos θ cos θ' / r² dA over the opening / E_outside, with cos θ = cos θ' = h/r and
  // L = Lz (1 + 2h/r)/3 (a 1000 × 1000 midpoint rule).
  const double h = 2.0, a = 1.0;
  const std::string room = R"(,
    {"type": "quad", "material": "black", "vertices": [[-4,2,-4],[4,2,-4],[4,2,-1],[-4,2,-1]]},
    {"type": "quad", "material": "black", "vertices": [[-4,2,1],[4,2,1],[4,2,4],[-4,2,4]]},
    {"type": "quad", "material": "black", "vertices": [[-4,2,-1],[-1,2,-1],[-1,2,1],[-4,2,1]]},
    {"type": "quad", "material": "black", "vertices": [[1,2,-1],[4,2,-1],[4,2,1],[1,2,1]]},
    {"type": "quad", "material": "black", "vertices": [[-4,0,-4],[-4,2,-4],[-4,2,4],[-4,0,4]]},
    {"type": "quad", "material": "black", "vertices": [[4,0,-4],[4,0,4],[4,2,4],[4,2,-4]]},
    {"type": "quad", "material": "black", "vertices": [[-4,0,-4],[4,0,-4],[4,2,-4],[-4,2,-4]]},
    {"type": "quad", "material": "black", "vertices": [[-4,0,4],[-4,2,4],[4,2,4],[4,0,4]]})";
  SceneDesc desc = test::sceneFromJson(groundScene(kOvercast, room));
  desc.materials[size_t(desc.findMaterial("ground"))].albedo = Color(0.0f);  // a black floor: nothing reflected
  constexpr int kN = 1000;
  double sum = 0.0;
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) {
      const double x = -a + 2 * a * (i + 0.5) / kN, z = -a + 2 * a * (j + 0.5) / kN;
      const double r = std::sqrt(x * x + z * z + h * h), c = h / r;
      sum += (1.0 + 2.0 * c) / 3.0 * c * c / (r * r);
    }
  const double lz = desc.sky->dome.zenithLuminance();
  const double expected = 100.0 * lz * sum * (4 * a * a / (double(kN) * kN)) / desc.sky->dome.horizontalIlluminance();
  const DfSample s = estimateDf(desc, {Vec3(0.0f, 0.0f, 0.0f), Vec3(0, 1, 0)}, 1 << 17);
  fmt::print("opening: DF {:.3f}% ± {:.3f}%, expected {:.3f}%\n", s.df, s.stderrDf, expected);
  EXPECT_GT(expected, 10.0);
  EXPECT_LT(s.stderrDf, 0.02 * expected);  // a sharp test
  EXPECT_LE(std::abs(s.df - expected), 3 * s.stderrDf + 0.005 * expected);  // + the baked map's 0.5%
}

TEST(DaylightFactor, CommandLineOutputs) {
  // A 4 × 2 grid on the open ground with the sun and lamps switched off: df_percent ≈ 100 per sensor within 4σ, the
  // summary on stdout, E_outside in the JSON, the picture's cells in the colours of the fixed 0–10% scale (clamped
  // at 10%: every cell the top colour).
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", groundScene(kSunAndLamps, kLampShape, kPointLight));
  const auto r = test::run(kRender + " " + dir + "/scene.json --daylight-factor --grid -1,-0.5,1,0.5,0.5,0.5 "
                           "--samples 1024 -o " + dir + "/df.csv -o " + dir + "/df.json --falsecolor " + dir +
                           "/df.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("E_outside 10000 lx"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("DF_median"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("switched off: lights[0] (\"bulb\"), sky.sun, material lamp"), std::string::npos) << r.output;
  std::ifstream csv(dir + "/df.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "x,y,z,nx,ny,nz,irradiance_r,irradiance_g,irradiance_b,illuminance_lux,stderr_lux,df_percent,"
                  "stderr_df_percent");
  int rows = 0;
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::vector<double> v;
    for (std::string f; std::getline(ss, f, ',');) v.push_back(std::stod(f));
    ASSERT_EQ(v.size(), 13u);
    EXPECT_NEAR(v[11], v[9] / 100.0, 1e-6 * v[11]);
    EXPECT_NEAR(v[12], v[10] / 100.0, 1e-6 * v[11]);
    EXPECT_LE(std::abs(v[11] - 100.0), 4 * v[12] + 0.5) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 8);
  const std::string json = test::readFile(dir + "/df.json");
  EXPECT_NE(json.find("\"E_outside_lux\": 10000,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"DF_avg\": "), std::string::npos);
  EXPECT_NE(json.find("\"df_percent\", \"stderr_df_percent\"]"), std::string::npos);
  int w = 0, hgt = 0;
  std::vector<std::string> ch;
  const auto px = Film::read(dir + "/df.png", w, hgt, ch);
  ASSERT_GT(w, 320);
  const auto top = falsecolor::colorMap(1.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[size_t(40 * w + 40) * 3 + size_t(k)] * 255.0, top[size_t(k)], 1.01);
}

TEST(DaylightFactor, DfPictureUsesTheFixedScale) {
  // A sensor 0.1 m above the ground under a black 10 × 10 m roof 1 m up sees the sky only below 10° of elevation: a
  // DF of a few percent, drawn in the colour of its place on the fixed 0–10% scale (an automatic range would put a
  // single value elsewhere).
  const std::string dir = test::tempDir();
  const std::string roof =
      R"(, {"type": "quad", "material": "black", "vertices": [[-5,1,-5],[5,1,-5],[5,1,5],[-5,1,5]]})";
  test::writeText(dir + "/scene.json", groundScene(kOvercast, roof));
  const auto r = test::run(kRender + " " + dir + "/scene.json -q --daylight-factor --grid -0.5,-0.5,0.5,0.5,0.1,1 "
                           "--samples 4096 -o " + dir + "/df.csv --falsecolor " + dir + "/df.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream csv(dir + "/df.csv");
  std::string line;
  std::getline(csv, line);
  std::getline(csv, line);
  std::stringstream ss(line);
  std::vector<double> v;
  for (std::string f; std::getline(ss, f, ',');) v.push_back(std::stod(f));
  ASSERT_EQ(v.size(), 13u);
  fmt::print("under the roof: DF {:.3f}% ± {:.3f}%\n", v[11], v[12]);
  ASSERT_GT(v[11], 0.5);
  ASSERT_LT(v[11], 9.5);
  int w = 0, hgt = 0;
  std::vector<std::string> ch;
  const auto px = Film::read(dir + "/df.png", w, hgt, ch);
  const auto c = falsecolor::colorMap(v[11] / 10.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[size_t(40 * w + 40) * 3 + size_t(k)] * 255.0, c[size_t(k)], 1.01);
}

TEST(DaylightFactor, BadInputExits2) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/clear.json", groundScene(R"("sky": {"type": "cie-clear", "horizontal_illuminance": 10000,
                                                            "sun": {"direction": [0, -1, 0], "illuminance": 1000}})"));
  test::writeText(dir + "/none.json", groundScene(R"("settings": {"spp": 1})", "", kPointLight));
  test::writeText(dir + "/lamps.json", groundScene(kSunAndLamps, kLampShape, kPointLight));
  const std::string grid = " --grid -1,-1,1,1,0.5,1 --samples 1 -o " + dir + "/out.csv";
  for (const char* scene : {"clear.json", "none.json"}) {
    const auto r = test::run(kRender + " " + dir + "/" + scene + " --daylight-factor" + grid);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(std::string(scene) + ": sky: the daylight factor needs"), std::string::npos) << r.output;
  }
  auto r = test::run(kRender + " " + dir + "/lamps.json --daylight-factor -o " + dir + "/out.png");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--daylight-factor: only with --sensors"), std::string::npos) << r.output;
  r = test::run(kRender + " " + dir + "/lamps.json --daylight-factor --firstshot " + dir + "/lamps.fsd" + grid);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("lamps.fsd: --firstshot: --daylight-factor switches"), std::string::npos) << r.output;
  SceneDesc noSky = test::sceneFromJson(groundScene(R"("settings": {"spp": 1})", "", kPointLight));
  EXPECT_THROW(daylightFactorScene(noSky), InputError);
}

// The shipped daylit office under sun, sky and downlights at the default patch size: the path tracer with and without
// the table (its default primary mode; every light sampled at every vertex), on the same camera samples; the image
// mean of the difference within 0.3% + 3σ of the NEE image's mean (as window-room in tests/test_thin_glass_render.cpp).
TEST(DaylightFactor, DaylitOfficeFirstShotAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("DaylightFactor.UnobstructedSensorIsOneHundredPercent");
  test::expectShippedSceneFirstShotAgreesWithNee("daylit-office");
}
