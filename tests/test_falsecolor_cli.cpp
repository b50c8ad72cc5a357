// firstshot-render's photometric outputs (render/cli/falsecolor_cli.h): --units luminance (cd/m² EXR)
// against K·Y of the radiance image and against the analytic luminance of a lit diffuse plane;
// --falsecolor of an image and of a grid (sizes, colours from the CSV's lux); bad values.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/lights/photometry.h"
#include "common/util/math.h"
#include "render/output/falsecolor.h"
#include "render/output/film.h"
#include "test_util.h"

using namespace firstshot;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;
constexpr double kPower = 100.0, kAlbedo = 0.5;  // W, point light 1 m over the plane

/// A point light 1 m over a 4 m × 4 m diffuse plane at y = 0, seen from 3 m above by a camera of
/// field of view @p fov (degrees).
std::string litPlane(double fov, int width, int height) {
  return fmt::format(R"({{
    "camera": {{"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": {}, "resolution": [{}, {}]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": {}}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]]}}],
    "lights": [{{"type": "point", "position": [0, 1, 0], "power": {}}}],
    "settings": {{"patch_size": 0.5, "spp": 4, "seed": 3}}}})", fov, width, height, kAlbedo, kPower);
}

std::vector<float> readImage(const std::string& path, int& w, int& h, std::vector<std::string>& channels) {
  return Film::read(path, w, h, channels);
}

/// Width and height of the picture at @p path.
std::pair<int, int> pictureSize(const std::string& path) {
  int w = 0, h = 0;
  std::vector<std::string> ch;
  readImage(path, w, h, ch);
  return {w, h};
}

}  // namespace

// --units luminance: one channel Y = K · Y(R, G, B) of the radiance image, for K = 179 and --efficacy 683.
TEST(FalseColorCli, LuminanceExrIsEfficacyTimesY) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", litPlane(60, 24, 16));
  auto r = test::run(kRender + " " + dir + "/scene.json -q -o " + dir + "/rad.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  int w = 0, h = 0;
  std::vector<std::string> ch;
  const auto rad = readImage(dir + "/rad.exr", w, h, ch);
  ASSERT_EQ(ch.size(), 3u);
  for (double k : {179.0, 683.0}) {
    const std::string out = fmt::format("{}/lum{}.exr", dir, k);
    r = test::run(kRender + " " + dir + "/scene.json -q --units luminance -o " + out +
                  (k == 179.0 ? "" : " --efficacy 683"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    int lw = 0, lh = 0;
    const auto lum = readImage(out, lw, lh, ch);
    ASSERT_EQ(ch, std::vector<std::string>{"Y"});
    ASSERT_EQ(lw, w);
    ASSERT_EQ(lh, h);
    double maxL = 0;
    for (size_t i = 0; i < lum.size(); ++i) {
      const Color c(rad[3 * i], rad[3 * i + 1], rad[3 * i + 2]);
      EXPECT_NEAR(lum[i], k * photometry::luminance(c), 1e-6 * lum[i] + 1e-9) << i;
      maxL = std::max(maxL, double(lum[i]));
    }
    EXPECT_GT(maxL, 0);
  }
}

// A diffuse plane of albedo ρ under irradiance E has radiance ρE/π; E = Φ/(4π h²) below a point light
// (h = 1 m). A 0.2° field of view sees only points within 5 mm of the foot, where E varies by < 10⁻⁴;
// the direct light is sampled exactly (one point light), so the only noise is the hit points'.
TEST(FalseColorCli, LuminanceOfLitPlaneIsAnalytic) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", litPlane(0.2, 4, 4));
  const auto r = test::run(kRender + " " + dir + "/scene.json -q --units luminance -o " + dir + "/lum.exr");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  int w = 0, h = 0;
  std::vector<std::string> ch;
  const auto lum = readImage(dir + "/lum.exr", w, h, ch);
  const double expected = photometry::kEfficacy * kAlbedo / kPi * kPower / (4 * kPi);  // cd/m², ≈ 226.7
  for (float l : lum) EXPECT_NEAR(l, expected, 2e-4 * expected);
}

// --falsecolor of a 32×24 image: scaled ×10 (longer side ≥ 320), legend 124 px, height ≥ 220.
TEST(FalseColorCli, ImagePicture) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", litPlane(60, 32, 24));
  const auto r = test::run(kRender + " " + dir + "/scene.json -q -o " + dir + "/img.png --falsecolor " + dir +
                           "/fc.png --falsecolor-contours 3");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto [w, h] = pictureSize(dir + "/fc.png");
  EXPECT_EQ(w, 320 + 124);
  EXPECT_EQ(h, 240);
}

// --grid with --falsecolor: one cell per sensor (4 × 2 cells scaled ×80), each of the colour of its
// CSV illuminance on the automatic linear range.
TEST(FalseColorCli, GridPicture) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", litPlane(60, 8, 8));
  const auto r = test::run(kRender + " " + dir + "/scene.json -q --grid -1,-0.5,1,0.5,0.05,0.5 --samples 8 -o " + dir +
                           "/grid.csv --falsecolor " + dir + "/grid.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream csv(dir + "/grid.csv");
  std::string line;
  std::getline(csv, line);
  std::vector<double> lux;
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::string f;
    for (int k = 0; k < 10; ++k) std::getline(ss, f, ',');
    lux.push_back(std::stod(f));
  }
  ASSERT_EQ(lux.size(), 8u);
  int w = 0, h = 0;
  std::vector<std::string> ch;
  const auto px = readImage(dir + "/grid.png", w, h, ch);
  ASSERT_EQ(w, 320 + 124);
  ASSERT_EQ(h, 220);
  const falsecolor::Range range = falsecolor::autoRange(lux, falsecolor::Scale::Linear);
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) {
      const auto c = falsecolor::colorMap(falsecolor::position(lux[size_t(j * 4 + i)], range, falsecolor::Scale::Linear));
      const size_t at = (size_t(j * 80 + 40) * size_t(w) + size_t(i * 80 + 40)) * 3;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[at + size_t(k)] * 255.0, c[size_t(k)], 1.01) << i << "," << j;
    }
}

// A grid on a named quad (--grid-quad, which joins after the scene is loaded) has a raster too: 4 × 4
// cells of the many-lights room's 8 m floor, scaled up by 80 to the 320 px minimum.
TEST(FalseColorCli, GridOnANamedQuadHasAPicture) {
  const std::string dir = test::tempDir();
  const auto r = test::run(kRender + " " + test::source("scenes/many-lights.json") + " -q --grid-quad floor,0.75,2 --samples 2 -o " +
                           dir + "/grid.csv --falsecolor " + dir + "/grid.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto [w, h] = pictureSize(dir + "/grid.png");
  EXPECT_EQ(w, 320 + 124);
  EXPECT_GE(h, 320);
}

namespace {

/// Runs firstshot-render on a small scene with each of @p cases (arguments, expected text in the
/// message) and asserts exit code 2, the message, and that no output file was left.
void expectBadValues(const std::string& dir, const std::vector<std::pair<std::string, std::string>>& cases) {
  for (const auto& [args, expected] : cases) {
    const auto r = test::run(kRender + " " + dir + "/scene.json -q " + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << "\n" << r.output;
    for (const char* f : {"/fc.png", "/img.exr", "/g.csv", "/p.csv"})
      EXPECT_FALSE(std::filesystem::exists(dir + f)) << args << ": " << f;
  }
}

std::string badValuesDir() {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", litPlane(60, 8, 8));
  test::writeText(dir + "/points.txt", "0 0 0 0 1 0\n");
  return dir;
}

}  // namespace

// Bad values exit 2 before any work and leave no file: the scale and the range.
TEST(FalseColorCli, BadScaleOrRangeExits2) {
  const std::string dir = badValuesDir();
  const std::string fc = " -o " + dir + "/img.exr --falsecolor " + dir + "/fc.png";
  expectBadValues(dir, {
      {fc + " --falsecolor-scale cubic", "--falsecolor-scale"},
      {fc + " --falsecolor-range 5,1", "MAX > MIN"},
      {fc + " --falsecolor-range 0,10", "MIN > 0"},
      {fc + " --falsecolor-range 1,x", "--falsecolor-range"},
      {fc + " --falsecolor-range 1,2,3", "--falsecolor-range"},
      {fc + " --falsecolor-contours 0", "--falsecolor-contours"},
  });
}

// Bad values exit 2: file names, options without the one they refine, options of the other mode.
TEST(FalseColorCli, BadOptionsExit2) {
  const std::string dir = badValuesDir();
  const std::string img = " -o " + dir + "/img.exr", grid = " --grid 0,0,1,1,0,0.5 -o " + dir + "/g.csv";
  expectBadValues(dir, {
      {img + " --falsecolor " + dir + "/fc.jpg", ".png"},
      {img + " --falsecolor " + dir + "/missing/fc.png", "folder"},
      {" -o " + dir + "/fc.png --falsecolor " + dir + "/fc.png", "overwrite"},
      {img + " --falsecolor-scale log", "only with --falsecolor"},
      {img + " --units lumens", "--units"},
      {img + " --efficacy 683", "--efficacy"},
      {" --sensors " + dir + "/points.txt -o " + dir + "/p.csv --falsecolor " + dir + "/fc.png", "--grid"},
      {grid + " --units luminance", "--units"},
      {grid + " --falsecolor " + dir + "/fc.png --falsecolor-range nan,4", "--falsecolor-range"},
  });
}
