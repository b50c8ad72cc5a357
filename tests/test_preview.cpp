// The preview window (render/preview/): the orbit camera's geometry, the camera JSON, the clear
// error without a display, and scripted runs under Xvfb compared with offline renders:
//  - after N frames the film is the offline render with --spp N, bit for bit (same seeds, same
//    per-pixel sample order), and the window shows exactly the offline PNG (±1 level of 8 bits);
//  - the instant picture equals the offline direct first-shot render (--primary patch
//    --max-depth 1) wherever a pixel lies inside one patch.
//  - the instant picture shows albedo textures: on a one-patch checker floor, texel × the patch's
//    flat shading per pixel, and elsewhere the untextured scene's picture byte for byte.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <optional>
#include <utility>

#include "common/formats/load_scene.h"
#include "render/scene/camera.h"
#include "render/output/film.h"
#include "render/output/image_io.h"
#include "render/integrators/path/integrator.h"
#include "render/preview/orbit_camera.h"
#include "render/preview/preview_app.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

const std::string kRender = FIRSTSHOT_RENDER_EXE;
const std::string kPreprocess = FIRSTSHOT_PREPROCESS_EXE;

std::string cornell() { return test::source("scenes/cornell.json"); }

bool haveXvfb() { return test::run("command -v xvfb-run").exitCode == 0; }

/// Preprocesses cornell into @p fsd with the Embree back end at resolution 32 and patch size 0.1.
void preprocessCornell(const std::string& fsd) {
  const auto pre = test::run(kPreprocess + " " + cornell() + " -o " + fsd + " --backend embree --resolution 32 --patch-size 0.1 -q");
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
}

/// Runs the preview under a virtual X server. -a picks a free display number; two servers
/// started at the same moment (tests in parallel) may still pick the same one, and then one fails
/// to start: try again. In the sanitizer build, LeakSanitizer's exit-time tracer has been seen to
/// crash ("Tracer caught signal 11") while suspending the windowed process's Mesa/X threads, so leak
/// checking is off for this child only (ASan and UBSan stay on; the offline renders keep it).
test::CommandResult runUnderXvfb(const std::string& args) {
  test::CommandResult r;
  for (int attempt = 0; attempt < 4; ++attempt) {
    r = test::run("env ASAN_OPTIONS=\"${ASAN_OPTIONS}:detect_leaks=0\" xvfb-run -a -s \"-screen 0 1024x768x24\" " + kRender +
                  " " + args);
    if (r.output.find("Xvfb failed to start") == std::string::npos) break;
  }
  return r;
}

struct Image {
  int width = 0, height = 0;
  std::vector<float> v;  ///< 3 channels
};

Image load(const std::string& path) {
  Image im;
  std::vector<std::string> channels;
  im.v = Film::read(path, im.width, im.height, channels);
  EXPECT_EQ(channels.size(), 3u) << path;
  return im;
}

/// Where a pixel of @p camera looks: the screen position of world point @p p, in pixels (x right, y down).
Vec2d project(const CameraDesc& c, const Vec3d& p) {
  const Vec3d f = glm::normalize(c.lookAt - c.position), r = glm::normalize(glm::cross(f, c.up)), u = glm::cross(r, f);
  const Vec3d d = p - c.position;
  const double t = std::tan(glm::radians(c.fovYDeg) * 0.5), aspect = double(c.width) / c.height;
  const double sx = glm::dot(d, r) / glm::dot(d, f) / (t * aspect), sy = glm::dot(d, u) / glm::dot(d, f) / t;
  return {(sx + 1) * 0.5 * c.width, (1 - sy) * 0.5 * c.height};
}

}  // namespace

TEST(PreviewCamera, UnmovedCameraIsTheScenesExactly) {
  CameraDesc c;
  c.position = {0.278, 0.273, -0.8};
  c.lookAt = {0.278, 0.273, 0.0};
  c.fovYDeg = 39.3077;
  const OrbitCamera cam(c);
  EXPECT_EQ(cam.desc().position, c.position);
  EXPECT_EQ(cam.desc().lookAt, c.lookAt);
  EXPECT_EQ(cam.desc().up, c.up);
  EXPECT_EQ(cam.desc().fovYDeg, c.fovYDeg);
}

TEST(PreviewCamera, OrbitPanDollyFly) {
  CameraDesc c;
  c.position = {1, 2, 5};
  c.lookAt = {0, 1, 0};
  c.width = 200, c.height = 100;
  OrbitCamera cam(c);
  const double d0 = cam.distance();

  // Orbiting keeps the distance and the look-at point; a full turn of yaw comes back.
  cam.orbit(0.7, 0.3);
  EXPECT_NEAR(cam.distance(), d0, 1e-12);
  EXPECT_EQ(cam.desc().lookAt, c.lookAt);
  EXPECT_GT(glm::length(cam.desc().position - c.position), 0.1);
  cam.orbit(0.0, -0.3);
  cam.orbit(2 * kPi - 0.7, 0.0);
  EXPECT_NEAR(glm::length(cam.desc().position - c.position), 0.0, 1e-12);
  // Pitch stops short of the up vector.
  cam.orbit(0.0, 10.0);
  cam.orbit(0.0, 1.5);
  EXPECT_LT(std::abs(glm::dot(cam.forward(), glm::normalize(c.up))), std::cos(glm::radians(0.99)));

  // Panning moves the look-at plane with the cursor: a point of that plane that was at pixel q
  // is afterwards at q + (dx, dy).
  OrbitCamera p(c);
  const Vec3d anchor = c.lookAt + 0.3 * p.right();
  const Vec2d before = project(p.desc(), anchor);
  p.pan(12.0, -7.0, c.height);
  const Vec2d after = project(p.desc(), anchor);
  EXPECT_NEAR(after.x - before.x, 12.0, 1e-9);
  EXPECT_NEAR(after.y - before.y, -7.0, 1e-9);

  // Dolly: distance × 0.9^steps, never below the minimum.
  OrbitCamera d(c);
  d.dolly(3.0, 0.01);
  EXPECT_NEAR(d.distance(), d0 * std::pow(0.9, 3.0), 1e-12);
  d.dolly(1000.0, 0.01);
  EXPECT_NEAR(d.distance(), 0.01, 1e-12);

  // Flying translates camera and target together.
  OrbitCamera f(c);
  f.fly(0.5, 0.0, 0.0);
  EXPECT_NEAR(glm::length(f.desc().position - c.position), 0.5, 1e-12);
  EXPECT_NEAR(f.distance(), d0, 1e-12);
}

TEST(PreviewCamera, JsonRoundTripsThroughTheSceneParser) {
  CameraDesc c;
  c.position = {0.1234567890123, -2.5, 1e-7};
  c.lookAt = {0.3, 0.2, 0.1};
  c.up = {0, 0, 1};
  c.fovYDeg = 39.3077;
  c.width = 321, c.height = 123;
  std::string text = "{";  // (appended, not "{" + ...: GCC 12 warns falsely about that)
  text += cameraJson(c);
  text += R"(, "materials": {"w": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "w", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}],
    "lights": [{"type": "point", "position": [0.5, 0.5, 1], "power": 1}]})";
  const SceneDesc s = test::sceneFromJson(text);
  EXPECT_EQ(s.camera.position, c.position);  // shortest round-trip decimals: exact
  EXPECT_EQ(s.camera.lookAt, c.lookAt);
  EXPECT_EQ(s.camera.up, c.up);
  EXPECT_EQ(s.camera.fovYDeg, c.fovYDeg);
  EXPECT_EQ(s.camera.width, 321);
  EXPECT_EQ(s.camera.height, 123);
}

TEST(PreviewCli, WithoutDisplayFailsWithAClearMessage) {
  const auto r = test::run("env -u DISPLAY -u WAYLAND_DISPLAY " + kRender + " " + cornell() + " --preview --width 16 --height 16");
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("firstshot-render: error: --preview needs a display ("));
  EXPECT_THAT(r.output, HasSubstr("use xvfb-run or render offline with -o"));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("Sanitizer")));
}

TEST(PreviewCli, BadScreenshotNameIsBadInput) {
  const std::string dir = test::tempDir();
  const auto r = test::run(kRender + " " + cornell() + " --preview --frames 1 --screenshot " + dir + "/shot.jpg");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(test::run(kRender + " " + cornell() + " --frames 1").exitCode, 2) << "--frames needs --preview";
}

TEST(PreviewCli, ScriptedRunEqualsTheOfflineRender) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = test::tempDir();
  const std::string fsd = dir + "/c.fsd";
  ASSERT_NO_FATAL_FAILURE(preprocessCornell(fsd));
  const int n = 6;
  const std::string common = cornell() + " --firstshot " + fsd + " --width 48 --height 40 --exposure 0.5";
  const auto offline = test::run(kRender + " " + common + " --spp " + std::to_string(n) + " -q -o " + dir + "/off.exr -o " + dir + "/off.png");
  ASSERT_EQ(offline.exitCode, 0) << offline.output;
  const auto preview = runUnderXvfb(common + " --preview --frames " + std::to_string(n) + " --screenshot " + dir +
                                    "/shot.png --window-grab " + dir + "/grab.png");
  ASSERT_EQ(preview.exitCode, 0) << preview.output;
  EXPECT_THAT(preview.output, HasSubstr(std::to_string(n) + " spp"));

  // The film: the same samples in the same order, so the same numbers.
  const Image off = load(dir + "/off.exr"), shot = load(dir + "/shot.exr");
  ASSERT_EQ(shot.width, 48);
  ASSERT_EQ(shot.height, 40);
  ASSERT_EQ(shot.v.size(), off.v.size());
  double maxDiff = 0;
  for (size_t i = 0; i < off.v.size(); ++i) maxDiff = std::max(maxDiff, double(std::abs(off.v[i] - shot.v[i])));
  fmt::print("preview EXR vs offline EXR ({} spp): max |difference| {}\n", n, maxDiff);
  EXPECT_EQ(maxDiff, 0.0);
  const Image offPng = load(dir + "/off.png"), shotPng = load(dir + "/shot.png");
  EXPECT_EQ(shotPng.v, offPng.v);

  // Not blank: the screenshot has structure (red and green walls, light, shadows).
  const double mean = std::accumulate(shotPng.v.begin(), shotPng.v.end(), 0.0) / double(shotPng.v.size());
  double var = 0;
  for (float x : shotPng.v) var += (x - mean) * (x - mean);
  var /= double(shotPng.v.size());
  fmt::print("screenshot: mean {:.3f}, standard deviation {:.3f} (8-bit levels / 255)\n", mean, std::sqrt(var));
  EXPECT_GT(mean, 0.05);
  EXPECT_GT(std::sqrt(var), 0.05);

  // The window: the display shader does what Film::write's PNG does (exposure, clamp, sRGB, 8 bits);
  // the GPU's pow and float-to-unorm rounding may move a value across a rounding boundary: ±1 level.
  const Image grab = load(dir + "/grab.png");
  ASSERT_EQ(grab.width, 48);
  ASSERT_EQ(grab.height, 40);
  double maxLevels = 0, sumLevels = 0;
  for (size_t i = 0; i < offPng.v.size(); ++i) {
    const double d = std::abs(double(grab.v[i]) - double(offPng.v[i])) * 255.0;
    maxLevels = std::max(maxLevels, d);
    sumLevels += d;
  }
  fmt::print("window vs offline PNG: max {} levels, mean {:.4f} levels\n", maxLevels, sumLevels / double(offPng.v.size()));
  EXPECT_LE(maxLevels, 1.0 + 1e-6);
  EXPECT_LT(sumLevels / double(offPng.v.size()), 0.05);
}

/// A scripted preview run of @p frames frames with the render options @p common (scene first)
/// gives the offline render of @p frames passes (`--spp`), bit for bit, and not a black one.
static void expectScriptedRunEqualsOffline(const std::string& common, int frames) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = test::tempDir(), n = std::to_string(frames);
  const auto offline = test::run(kRender + " " + common + " --spp " + n + " -q -o " + dir + "/off.exr");
  ASSERT_EQ(offline.exitCode, 0) << offline.output;
  const auto preview = runUnderXvfb(common + " --preview --frames " + n + " --screenshot " + dir + "/shot.png");
  ASSERT_EQ(preview.exitCode, 0) << preview.output;
  const Image off = load(dir + "/off.exr"), shot = load(dir + "/shot.exr");
  ASSERT_EQ(shot.v.size(), off.v.size());
  EXPECT_EQ(shot.v, off.v);
  EXPECT_GT(std::accumulate(off.v.begin(), off.v.end(), 0.0), 0.0);
}

/// The ray-bundle integrator in the preview: pass k runs iteration k, so N frames equal an offline
/// render of N iterations (--spp N is --iterations N), bit for bit.
TEST(PreviewCli, BundleScriptedRunEqualsTheOfflineRender) {
  expectScriptedRunEqualsOffline(cornell() + " --integrator bundle --bundle-resolution 64 --width 32 --height 24", 4);
}

/// Bidirectional path tracing in the preview: pass k is sample index k of the splat loop, so N
/// frames equal an offline render of N spp, bit for bit.
TEST(PreviewCli, BdptScriptedRunEqualsTheOfflineRender) {
  expectScriptedRunEqualsOffline(cornell() + " --integrator bdpt --width 32 --height 24", 3);
}

/// --sampler sobol in the preview: pass k is sample k of every pixel's sequence, so N
/// frames equal the offline render, bit for bit (the path tracer and a splatting integrator).
TEST(PreviewCli, SobolScriptedRunEqualsTheOfflineRender) {
  expectScriptedRunEqualsOffline(cornell() + " --sampler sobol --width 32 --height 24", 4);
  expectScriptedRunEqualsOffline(cornell() + " --sampler sobol --integrator light --width 32 --height 24", 3);
}

TEST(PreviewCli, InstantPictureIsTheDirectFirstShotRender) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = test::tempDir();
  const std::string fsd = dir + "/c.fsd";
  ASSERT_NO_FATAL_FAILURE(preprocessCornell(fsd));
  const std::string common = cornell() + " --firstshot " + fsd + " --width 64 --height 64";
  // Direct light only, first-shot at the camera-visible patch. The instant picture is flat per
  // patch side (the patch-averaged irradiance, FirstShotTable::sideIrradiance); the offline render
  // evaluates the first-shot term per point (render/firstshot/lighting.h), whose average over a patch is
  // that same value. With every light of the Cornell box replaced there is no noise, and the two
  // pictures agree on the whole up to how unevenly the pixels sample each patch (0.1 m patches:
  // the flat picture measured 5.3% darker, the bias that per-point evaluation removes).
  const auto offline = test::run(kRender + " " + common + " --primary patch --max-depth 1 --spp 16 -q -o " + dir + "/direct.exr");
  ASSERT_EQ(offline.exitCode, 0) << offline.output;
  const auto preview = runUnderXvfb(common + " --preview --frames 0 --screenshot " + dir + "/instant.png");
  ASSERT_EQ(preview.exitCode, 0) << preview.output;
  EXPECT_THAT(preview.output, HasSubstr("instant picture"));

  const Image direct = load(dir + "/direct.exr"), instant = load(dir + "/instant.exr");
  ASSERT_EQ(direct.v.size(), instant.v.size());
  const int w = direct.width, h = direct.height;
  auto at = [&](const Image& im, int x, int y, int c) { return double(im.v[(size_t(y) * w + x) * 3 + c]); };
  auto equal = [](double a, double b) { return std::abs(a - b) <= 1e-5 * std::max(1.0, std::abs(a)); };
  double sumInstant = 0, sumDirect = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) sumInstant += at(instant, x, y, c), sumDirect += at(direct, x, y, c);
  const double pixels = double(w) * h;
  fmt::print("instant vs direct first-shot: image sums {:.4f} vs {:.4f}\n", sumInstant, sumDirect);
  EXPECT_GT(sumInstant, 0.0);
  EXPECT_NEAR(sumInstant, sumDirect, 0.1 * sumDirect);

  // The exact definition of the instant picture: ρ/π × the patch-averaged first-shot irradiance on
  // the viewer's side (or the emitted radiance) where the ray through each pixel's centre lands.
  // Raster and ray casting may disagree only for a centre within float rounding of an edge (none at
  // this size; allow 1 %).
  SceneDesc desc = loadScene(cornell());
  desc.camera.width = w, desc.camera.height = h;
  const RenderScene scene(desc, readFirstShot(fsd), fsd);
  const std::vector<Color> side = scene.firstShot()->sideIrradiance();
  const Camera camera(desc.camera);
  size_t exact = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray ray = camera.generateRay(float(x) + 0.5f, float(y) + 0.5f);
      Hit hit;
      Color expected(0.0f);
      if (scene.intersect(ray, hit)) {
        const Vec3 wo = -ray.d;
        const Frame frame(hit.ng);
        const Vec3 woLocal = frame.toLocal(wo);
        const bool front = woLocal.z > 0.0f;
        expected = hit.onPatch() ? scene.bsdf(scene.material(hit)).eval(BSDFQuery(Vec3(0, 0, front ? 1 : -1), woLocal)) *
                                       side[2 * size_t(hit.patch) + (front ? 0 : 1)]
                                 : scene.lights().emitted(hit, wo);
      }
      bool ok = true;
      for (int c = 0; c < 3; ++c) ok = ok && equal(expected[c], at(instant, x, y, c));
      exact += ok;
    }
  fmt::print("instant vs ray cast at pixel centres: {:.2f}% of pixels equal\n", 100 * exact / pixels);
  EXPECT_GE(exact / pixels, 0.99);
}

TEST(PreviewCli, WithoutTableShowsAHeadlightPicture) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = test::tempDir();
  const auto r = runUnderXvfb(cornell() + " --preview --width 32 --height 32 --frames 0 --screenshot " + dir + "/h.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const Image im = load(dir + "/h.exr");
  // Headlight shading: albedo × |cos| ≤ the largest albedo (0.725) except on the light (17, 12, 4).
  size_t lit = 0, light = 0;
  for (size_t p = 0; p < im.v.size() / 3; ++p) {
    const float m = std::max({im.v[3 * p], im.v[3 * p + 1], im.v[3 * p + 2]});
    lit += m > 0.05f && m <= 0.7251f;
    light += m >= 3.99f;
  }
  EXPECT_GT(lit, im.v.size() / 3 / 2) << "most pixels see a lit surface";
  EXPECT_GT(light, 0u) << "the light is visible";
}

namespace {

/// The two colours of the checker texture below (linear RGB, very different chroma: r/b = 16 and 1/16).
const Color kCheckerA(0.8f, 0.2f, 0.05f), kCheckerB(0.05f, 0.2f, 0.8f);

/// Writes @p dir/scene.json: a 1 m floor quad (x ∈ [0, 1], z ∈ [−1, 0], uv = (x, 1 + z)) with an 8 × 8-texel EXR
/// whose 4 × 4 blocks make a 2 × 2 checker (A top left and bottom right), wrap clamp, factor 1; a grey back wall;
/// a point light. Without @p textured the floor is plain grey instead. Every face is one patch (patch_size 2).
void writeCheckerScene(const std::string& dir, bool textured) {
  std::vector<float> texels;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const Color c = ((x >= 4) != (y >= 4)) ? kCheckerB : kCheckerA;
      texels.insert(texels.end(), {c.x, c.y, c.z});
    }
  image::writeExr(dir + "/checker.exr", 8, 8, {"R", "G", "B"}, texels.data());
  const std::string floor = textured ? R"({"type": "diffuse", "albedo_texture": {"file": "checker.exr", "wrap": "clamp"}})"
                                     : R"({"type": "diffuse", "albedo": 0.5})";
  test::writeText(dir + "/scene.json", R"({
    "camera": {"position": [0.5, 1.1, 0.5], "look_at": [0.5, 0.0, -0.5], "fov_y": 60, "resolution": [96, 96]},
    "settings": {"patch_size": 2, "min_patch_size": 2},
    "materials": {"floor": )" + floor + R"(, "wall": {"type": "diffuse", "albedo": 0.6}},
    "shapes": [
      {"type": "quad", "material": "floor", "vertices": [[0, 0, 0], [1, 0, 0], [1, 0, -1], [0, 0, -1]]},
      {"type": "quad", "material": "wall", "vertices": [[-1, 0, -1], [2, 0, -1], [2, 2, -1], [-1, 2, -1]]}],
    "lights": [{"type": "point", "position": [0.4, 0.8, -0.3], "power": 5}]})");
}

/// The checker's colour at floor texture coordinates @p uv, or nullopt where the bilinear lookup blends the
/// blocks (texel centres of one block span [1/16, 7/16] of the image; clamp makes the outer borders flat), with
/// a margin of 0.01 in uv for the raster's rounding (a pixel covers about 0.02 of the floor).
std::optional<Color> checkerAt(const Vec2& uv) {
  const auto flat = [](float t) { return t >= 0.0f && t <= 1.0f && std::abs(t - 0.5f) >= 1.0f / 16.0f + 0.01f; };
  if (!flat(uv.x) || !flat(uv.y)) return std::nullopt;
  return (uv.x < 0.5f) != (uv.y < 0.5f) ? kCheckerB : kCheckerA;
}

/// Runs the preview's instant picture of @p dir/scene.json (with the table @p fsd when not empty) and returns it.
Image instantPicture(const std::string& dir, const std::string& fsd, const std::string& name) {
  const auto r = runUnderXvfb(dir + "/scene.json" + (fsd.empty() ? "" : " --firstshot " + fsd) + " --preview --frames 0 --screenshot " +
                              dir + "/" + name + ".png");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  return load(dir + "/" + name + ".exr");
}

}  // namespace

/// The instant picture shows albedo textures. A diffuse patch side's radiance is ∝ its albedo, so
/// the raster multiplies the patch's flat colour by ρ(x)/ρ̄(patch): on the one-patch checker floor each pixel
/// must be texel × (E_side/π with the table, |cos θ| under the headlight) — exact up to float rounding, where
/// the patch average alone would show one mixed colour (r/b ≈ 1 instead of 16 and 1/16). And the textures leave
/// everything else alone: outside the floor the picture is the untextured scene's, byte for byte.
TEST(PreviewCli, InstantPictureShowsTextures) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  for (const bool table : {false, true}) {
    SCOPED_TRACE(table ? "first-shot table" : "headlight");
    const std::string dir = test::tempDir(), plainDir = test::tempDir();
    writeCheckerScene(dir, true);
    writeCheckerScene(plainDir, false);
    std::string fsd, plainFsd;
    if (table) {
      fsd = dir + "/s.fsd", plainFsd = plainDir + "/s.fsd";
      for (const auto& [sceneDir, out] : {std::pair{dir, fsd}, std::pair{plainDir, plainFsd}}) {
        const auto pre = test::run(kPreprocess + " " + sceneDir + "/scene.json -o " + out + " --backend embree --resolution 16 -q");
        ASSERT_EQ(pre.exitCode, 0) << pre.output;
      }
    }
    const Image textured = instantPicture(dir, fsd, "t"), plain = instantPicture(plainDir, plainFsd, "p");
    ASSERT_EQ(textured.width, 96);
    ASSERT_EQ(textured.v.size(), plain.v.size());

    // Ray-cast every pixel centre: the floor point, its uv and the expected radiance.
    SceneDesc desc = loadScene(dir + "/scene.json");
    const RenderScene scene = table ? RenderScene(desc, readFirstShot(fsd), fsd) : RenderScene(desc);
    const std::vector<Color> side = table ? scene.firstShot()->sideIrradiance() : std::vector<Color>();
    const Camera camera(desc.camera);
    size_t checked[2][2] = {}, wrong = 0, differOffFloor = 0, sameLit = 0;
    Vec3d sumA(0.0), sumB(0.0);
    for (int y = 0; y < textured.height; ++y)
      for (int x = 0; x < textured.width; ++x) {
        const size_t i = (size_t(y) * size_t(textured.width) + size_t(x)) * 3;
        const Color got(textured.v[i], textured.v[i + 1], textured.v[i + 2]);
        const Ray ray = camera.generateRay(float(x) + 0.5f, float(y) + 0.5f);
        Hit hit;
        const bool floor = scene.intersect(ray, hit) && hit.onPatch() && scene.mesh().patches[hit.patch].shape == 0;
        if (!floor) {
          const bool same = std::equal(&textured.v[i], &textured.v[i + 3], &plain.v[i]);
          differOffFloor += !same;
          sameLit += same && got.x > 0.0f;
          continue;
        }
        const Vec2 uv(hit.p.x, 1.0f + hit.p.z);
        const std::optional<Color> texel = checkerAt(uv);
        if (!texel) continue;
        const Vec3 toEye = Vec3(desc.camera.position) - hit.p;
        const float c = glm::dot(hit.ng, toEye) / glm::length(toEye);
        const Color expected = *texel * (table ? side[2 * size_t(hit.patch) + (c > 0 ? 0 : 1)] * kInvPiF : Color(std::abs(c)));
        // Float rounding of ~6 factors and the raster's interpolated position (in |cos θ|): well below 1e-3.
        bool ok = true;
        for (int k = 0; k < 3; ++k) ok = ok && std::abs(got[k] - expected[k]) <= 1e-3f * expected[k];
        wrong += !ok;
        if (!ok && wrong <= 3)
          ADD_FAILURE() << "pixel (" << x << ", " << y << ") uv (" << uv.x << ", " << uv.y << "): got " << got.x << " " << got.y << " "
                        << got.z << ", expected " << expected.x << " " << expected.y << " " << expected.z;
        ++checked[uv.x < 0.5f][uv.y < 0.5f];
        (*texel == kCheckerA ? sumA : sumB) += Vec3d(got);
      }
    // The two colours in their places: every cell seen by many pixels, and the chroma of each colour's
    // region mean (r/b) is the texel's: 16 and 1/16, to float rounding.
    for (const auto& row : checked)
      for (size_t n : row) EXPECT_GT(n, 50u);
    EXPECT_EQ(wrong, 0u);
    const double ratioA = sumA.x / sumA.z, ratioB = sumB.x / sumB.z;
    fmt::print("textured instant picture ({}): r/b of the regions' means {:.5f} (texel 16) and {:.6f} (texel 0.0625); "
               "{} pixels checked; off the floor {} pixels differ, {} lit ones equal\n",
               table ? "first-shot" : "headlight", ratioA, ratioB, checked[0][0] + checked[0][1] + checked[1][0] + checked[1][1],
               differOffFloor, sameLit);
    EXPECT_NEAR(ratioA, 16.0, 16.0 * 1e-4);
    EXPECT_NEAR(ratioB, 1.0 / 16.0, 1e-4 / 16.0);
    EXPECT_EQ(differOffFloor, 0u);
    EXPECT_GT(sameLit, 500u) << "the wall is visible";
  }
}

namespace {

/// Writes @p dir/scene.json: a black screen (x, y ∈ [0, 1] at z = −0.5, uv = (x, 1 − y)) whose alpha texture is an
/// 8 × 8-texel EXR (first channel) of 4 × 4 blocks, 1 in the top-left and bottom-right ones and 0 in the others,
/// wrap clamp, alpha mode mask; a grey wall behind it; the camera looking at the screen through its middle.
void writeCutoutScene(const std::string& dir) {
  std::vector<float> texels;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const float a = ((x >= 4) != (y >= 4)) ? 0.0f : 1.0f;
      texels.insert(texels.end(), {a, a, a});
    }
  image::writeExr(dir + "/alpha.exr", 8, 8, {"R", "G", "B"}, texels.data());
  test::writeText(dir + "/scene.json", R"({
    "camera": {"position": [0.5, 0.5, 1], "look_at": [0.5, 0.5, -0.5], "fov_y": 60, "resolution": [96, 96]},
    "settings": {"patch_size": 2, "min_patch_size": 2},
    "materials": {"screen": {"type": "diffuse", "albedo": 0, "alpha_mode": "mask",
                             "alpha_texture": {"file": "alpha.exr", "wrap": "clamp"}},
                  "wall": {"type": "diffuse", "albedo": 0.6}},
    "shapes": [
      {"type": "quad", "material": "screen", "vertices": [[0, 0, -0.5], [1, 0, -0.5], [1, 1, -0.5], [0, 1, -0.5]]},
      {"type": "quad", "material": "wall", "vertices": [[-1, -1, -1], [2, -1, -1], [2, 2, -1], [-1, 2, -1]]}],
    "lights": [{"type": "point", "position": [0.4, 0.8, 0.3], "power": 5}]})");
}

}  // namespace

/// The instant picture draws alpha cut-outs. Under the headlight the black screen shows black where it
/// exists and the lit wall through its holes: every pixel centre whose ray (RenderScene::intersect, which honours
/// cut-outs) meets the screen is black, every other is lit — except those whose ray meets the screen's plane within
/// 0.01 in uv of a block boundary or its edge, where the raster's rounding may decide either way.
TEST(PreviewCli, InstantPictureShowsCutouts) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = test::tempDir();
  writeCutoutScene(dir);
  const Image picture = instantPicture(dir, "", "c");
  ASSERT_EQ(picture.width, 96);
  const SceneDesc desc = loadScene(dir + "/scene.json");
  const RenderScene scene(desc);
  ASSERT_NE(scene.cutouts(), nullptr);
  const Camera camera(desc.camera);
  size_t wrong = 0, holes = 0, solid = 0;
  for (int y = 0; y < picture.height; ++y)
    for (int x = 0; x < picture.width; ++x) {
      const Ray ray = camera.generateRay(float(x) + 0.5f, float(y) + 0.5f);
      const float t = (-0.5f - ray.o.z) / ray.d.z;
      const Vec3 p = ray.o + t * ray.d;
      const Vec2 uv(p.x, 1.0f - p.y);
      const auto near = [](float c) { return std::abs(c) < 0.01f || std::abs(c - 0.5f) < 0.01f || std::abs(c - 1.0f) < 0.01f; };
      if (near(uv.x) || near(uv.y)) continue;
      Hit hit;
      ASSERT_TRUE(scene.intersect(ray, hit));
      const bool onScreen = scene.mesh().patches[hit.patch].shape == 0;
      const bool inside = uv.x > 0.0f && uv.x < 1.0f && uv.y > 0.0f && uv.y < 1.0f;
      if (inside) (onScreen ? solid : holes) += 1;
      const float value = picture.v[(size_t(y) * size_t(picture.width) + size_t(x)) * 3 + 1];
      if ((value == 0.0f) != onScreen && ++wrong <= 3)
        ADD_FAILURE() << "pixel (" << x << ", " << y << ") uv (" << uv.x << ", " << uv.y << "): " << value
                      << (onScreen ? ", the screen exists there" : ", a hole or beside the screen");
    }
  fmt::print("cut-out instant picture: {} pixels through holes, {} on the screen, {} wrong\n", holes, solid, wrong);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(holes, 500u);
  EXPECT_GT(solid, 500u);
}

/// An emitter with an emission texture shows factor × texel per point in the instant picture (a quad at
/// z = −0.5 facing the camera, uv = (x, 1 − y), the checker of writeCheckerScene as its emission texture, factor 2).
TEST(PreviewCli, InstantPictureShowsEmissionTextures) {
  if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = test::tempDir();
  writeCheckerScene(dir, true);  // for checker.exr
  test::writeText(dir + "/scene.json", R"({
    "camera": {"position": [0.5, 0.5, 1], "look_at": [0.5, 0.5, -0.5], "fov_y": 60, "resolution": [96, 96]},
    "settings": {"patch_size": 2, "min_patch_size": 2},
    "materials": {"sign": {"type": "diffuse", "albedo": 0, "emission": 2,
                           "emission_texture": {"file": "checker.exr", "wrap": "clamp"}},
                  "wall": {"type": "diffuse", "albedo": 0.6}},
    "shapes": [
      {"type": "quad", "material": "sign", "vertices": [[0, 0, -0.5], [1, 0, -0.5], [1, 1, -0.5], [0, 1, -0.5]]},
      {"type": "quad", "material": "wall", "vertices": [[-1, -1, -1], [2, -1, -1], [2, 2, -1], [-1, 2, -1]]}]})");
  const Image picture = instantPicture(dir, "", "e");
  ASSERT_EQ(picture.width, 96);
  const SceneDesc desc = loadScene(dir + "/scene.json");
  const Camera camera(desc.camera);
  size_t checked[2] = {}, wrong = 0;
  for (int y = 0; y < picture.height; ++y)
    for (int x = 0; x < picture.width; ++x) {
      const Ray ray = camera.generateRay(float(x) + 0.5f, float(y) + 0.5f);
      const Vec3 p = ray.o + ((-0.5f - ray.o.z) / ray.d.z) * ray.d;
      const std::optional<Color> texel = checkerAt(Vec2(p.x, 1.0f - p.y));
      if (!texel) continue;
      const Color expected = 2.0f * *texel;
      const size_t i = (size_t(y) * size_t(picture.width) + size_t(x)) * 3;
      bool ok = true;
      for (int k = 0; k < 3; ++k) ok = ok && std::abs(picture.v[i + size_t(k)] - expected[k]) <= 1e-3f * expected[k];
      if (!ok && ++wrong <= 3)
        ADD_FAILURE() << "pixel (" << x << ", " << y << "): got " << picture.v[i] << " " << picture.v[i + 1] << " "
                      << picture.v[i + 2] << ", expected " << expected.x << " " << expected.y << " " << expected.z;
      ++checked[*texel == kCheckerA];
    }
  fmt::print("emission texture in the instant picture: {} + {} pixels checked, {} wrong\n", checked[0], checked[1], wrong);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(checked[0], 300u);
  EXPECT_GT(checked[1], 300u);
}
