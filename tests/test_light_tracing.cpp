// Light tracing (--integrator light): images against path tracing per 8×8 block, reciprocity of
// the BSDFs and of one transport path, bit-identical images for any thread count, and the CLI.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "common/sampling/sampling.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/common/camera_splat.h"
#include "tests/block_compare.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"
#include "tests/splat_checks.h"
#include "tests/test_util.h"

using namespace firstshot;

using test::blockMeans;
using test::expectBlocksAgree;

// The area light of the Cornell box is seen directly: light tracing draws it by connecting the
// particles' first vertex (on the light) to the camera, so no block is left out.
TEST(LightTracing, CornellImageAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("LightTracing.MirrorAndGlassAgreeWithPathTracing");
  test::expectAgreesWithPathTracing("light", "cornell", 600, 300);
}
TEST(LightTracing, ManyLightsImageAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("LightTracing.MirrorAndGlassAgreeWithPathTracing");
  test::expectAgreesWithPathTracing("light", "many-lights", 600, 300);
}
TEST(LightTracing, SierpinskiGlossyImageAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("LightTracing.MirrorAndGlassAgreeWithPathTracing");
  test::expectAgreesWithPathTracing("light", "sierpinski-glossy", 600, 300);
}

// Delta surfaces: a mirror and a glass block seen by the camera (their pixels are path traced)
// and the glass's caustic on the floor (light tracing carries it through the adjoint refraction;
// path tracing finds it only when a BSDF sample meets the light).
TEST(LightTracing, MirrorAndGlassAgreeWithPathTracing) {
  test::expectAgreesWithPathTracing("light", "mirror-glass", test::mirrorGlassScene(), 600, 300);
}

// With a first-shot table the small lights stay lights for shooting: the same image as without.
// With --shoot-firstshot off the table's small lights are shot like all others.
TEST(LightTracing, FirstShotTableLeavesTheImageUnchanged) {
  FIRSTSHOT_STATISTICS_ONLY("Integrators/ShootingFirstShot.MixedLightsAgreeWithPathTracingOnTheSameTable/light");
  IntegratorOptions io;
  io.shootFromPatches = false;
  test::expectTableLeavesImageUnchanged("light", 300, io);
}

// f(ωi, ωo) = f(ωo, ωi) for the non-delta BSDFs, on random pairs of directions (both hemispheres).
TEST(LightTracing, BsdfsAreReciprocal) {
  const std::vector<BSDF> bsdfs = {LambertBRDF{Color(0.7f, 0.5f, 0.2f)},
                                   StretchedPhongBRDF(Color(0.2f), Color(0.5f, 0.4f, 0.3f), 3.0f),
                                   StretchedPhongBRDF(Color(0.05f), Color(2.0f), 40.0f)};
  Sampler s(1, 2, 3);
  int nonZero = 0;
  for (const BSDF& bsdf : bsdfs)
    for (int i = 0; i < 2000; ++i) {
      const Vec3 a = squareToUniformSphere(s.next2D()), b = squareToUniformSphere(s.next2D());
      for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
        const Color f = bsdf.eval(BSDFQuery(a, b, mode)), g = bsdf.eval(BSDFQuery(b, a, mode));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], g[c], 1e-5f * std::max(1.0f, f[c]));
        nonZero += maxComponent(f) > 0.0f;
      }
    }
  EXPECT_GT(nonZero, 3000);  // about half the pairs lie on one side
}

// One path light → x1 → x2 → camera (area light, glossy x1, diffuse x2): the light tracer's
// connection of x2, with the particle's throughput in area measure, weighs the same as the
// camera's side: W_e·G(camera, x2)·f(x2)·G(x2, x1)·f(x1)·G(x1, y)·Le, with W_e from the camera's
// field of view (1/(A_pixel cos⁴θ)) and the BSDFs evaluated in the gathering direction.
TEST(LightTracing, TransportPathWeighsTheSameBothWays) {
  SceneDesc d = test::sceneFromJson(R"({"materials": {"d": {"type": "diffuse", "albedo": [0.6, 0.5, 0.4]},
      "g": {"type": "glossy", "albedo": 0.2, "specular": 0.5, "exponent": 8}, "lamp": {"type": "diffuse", "emission": [5, 4, 3]}},
    "shapes": [{"type": "quad", "material": "d", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "quad", "material": "g", "vertices": [[1.5,-1,-1],[1.5,1,-1],[1.5,1,1],[1.5,-1,1]]},
               {"type": "quad", "material": "lamp", "vertices": [[-0.1,2,-0.1],[0.1,2,-0.1],[0.1,2,0.1],[-0.1,2,0.1]]}],
    "camera": {"position": [0, 1, -3], "look_at": [0, 0, 0], "fov_y": 50, "resolution": [40, 30]}})");
  const RenderScene scene(d, 0.5);
  LightTracingIntegrator lt{IntegratorOptions()};
  lt.preprocess(scene);
  const Camera camera(d.camera);
  const Vec3 y(0.02f, 2.0f, 0.01f), ny(0, -1, 0), x1(1.5f, 0.6f, 0.2f), n1(-1, 0, 0), x2(0.3f, 0.0f, -0.2f), n2(0, 1, 0);
  const Vec3 c = camera.position();
  auto G = [](const Vec3& a, const Vec3& na, const Vec3& b, const Vec3& nb) {
    const Vec3 ab = b - a;
    const float d2 = glm::dot(ab, ab), len = std::sqrt(d2);
    return std::abs(glm::dot(na, ab) / len) * std::abs(glm::dot(nb, ab) / len) / d2;
  };
  auto f = [&](const Vec3& n, const Vec3& towardsLight, const Vec3& towardsEye, const char* m) {
    const Frame fr(n);
    return scene.bsdf(uint32_t(d.findMaterial(m))).eval(BSDFQuery(fr.toLocal(glm::normalize(towardsLight)),
                                                                   fr.toLocal(glm::normalize(towardsEye))));
  };
  const Color Le(5, 4, 3);
  // Light side: the particle's throughput at x2, then the light tracer's connection.
  LightVertex v;
  v.hit.p = x2, v.hit.ng = n2, v.hit.patch = 0, v.hit.eps = 1e-5f;
  v.wi = glm::normalize(x1 - x2);
  v.material = uint32_t(d.findMaterial("d"));
  v.beta = Le * G(y, ny, x1, n1) * f(n1, y - x1, x2 - x1, "g") * G(x1, n1, x2, n2);
  uint32_t pixel = 0;
  Color light(0.0f);
  uint64_t rays = 0;
  ASSERT_TRUE(connectToCamera(scene, v, camera, pixel, light, rays, false));
  // Camera side, from the camera's own description.
  const Vec3 wc = glm::normalize(x2 - c), fwd = glm::normalize(Vec3(d.camera.lookAt) - c);
  const float cosC = glm::dot(wc, fwd), tanHalf = std::tan(glm::radians(float(d.camera.fovYDeg)) * 0.5f);
  const float aPixel = (2 * tanHalf) * (2 * tanHalf * 40.0f / 30.0f) / (40.0f * 30.0f);
  const float We = 1.0f / (aPixel * std::pow(cosC, 4.0f));
  const float cameraG = cosC * std::abs(glm::dot(n2, wc)) / glm::dot(x2 - c, x2 - c);
  const Color eye = We * cameraG * f(n2, x1 - x2, c - x2, "d") * G(x2, n2, x1, n1) * f(n1, y - x1, x2 - x1, "g") *
                    G(x1, n1, y, ny) * Le;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(light[k], eye[k], 1e-4f * eye[k]);
  EXPECT_GT(maxComponent(eye), 0.0f);
  // And the pixel is the one the camera ray through x2 starts in.
  Hit hit;
  const Ray r = camera.generateRay(float(pixel % 40) + 0.5f, float(pixel / 40) + 0.5f);
  ASSERT_TRUE(scene.intersect(r, hit));
  EXPECT_LT(glm::length(hit.p - x2), 0.3f);
}

// The image does not depend on the number of threads, and passes rendered one at a time give
// the film of one render.
TEST(LightTracing, BitIdenticalForOneAndTwoThreadsAndByPasses) {
  const test::RenderRun one = test::expectSameFilmForThreadsAndPasses("light");
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) EXPECT_EQ(one.film.samples(x, y), 3u);
  EXPECT_GT(one.stats.rays, uint64_t(3 * 1200));
}

// --light-paths K: K light paths per pixel in each pass; 0 (the default) is 8, fewer where a pass
// would hold more than 2^21 paths' splats, and 1 where a mirror or glass makes the camera samples
// carry what is seen through it. Any K gives the same expected image: the agreement tests above
// run at 8 (cornell, many-lights, sierpinski-glossy) and at 1 (mirror and glass), and would be K
// times off if the splats were not divided by all of a pass's particles.
TEST(LightTracing, LightPathsPerPass) {
  SceneDesc cornell = loadScene(test::source("scenes/cornell.json")), mirrors = test::mirrorGlassScene();
  const RenderScene diffuseScene(cornell, cornell.settings.patchSize), deltaScene(mirrors, mirrors.settings.patchSize);
  const auto camera = [&](int w, int h) {
    CameraDesc c = cornell.camera;
    c.width = w, c.height = h;
    return Camera(c);
  };
  for (const int k : {0, 1, 3}) {
    IntegratorOptions io;
    io.lightPathsPerPixel = k;
    LightTracingIntegrator a(io), b(io);
    a.preprocess(diffuseScene);
    b.preprocess(deltaScene);
    EXPECT_EQ(a.pathsPerPixel(camera(32, 24)), k > 0 ? k : LightTracingIntegrator::kAutoPathsPerPixel) << k;
    EXPECT_EQ(a.pathsPerPixel(camera(640, 480)), k > 0 ? k : 6) << k;  // 2^21 / 307,200 pixels
    EXPECT_EQ(a.pathsPerPixel(camera(1920, 1080)), k > 0 ? k : 1) << k;
    EXPECT_EQ(b.pathsPerPixel(camera(32, 24)), k > 0 ? k : 1) << k;
    EXPECT_EQ(a.particlesPerPass(camera(32, 24)), uint64_t(a.pathsPerPixel(camera(32, 24))) * 32u * 24u) << k;
  }
  const std::string render = std::string(FIRSTSHOT_RENDER_EXE) + " " + test::source("scenes/cornell.json") +
                             " --integrator light --spp 1 -q -o " + test::tempDir() + "/k.exr";
  const auto ok = test::run(render + " --width 24 --height 20 --light-paths 2");
  EXPECT_EQ(ok.exitCode, 0) << ok.output;
  // Out of range, not a number, and more splats per pass than the machine's memory (2^12 paths per
  // pixel of 2^24 pixels: petabytes), refused before anything is rendered.
  for (const char* bad : {"-1 --width 24 --height 20", "two --width 24 --height 20", "5000 --width 24 --height 20",
                          "4096 --width 4096 --height 4096"}) {
    const auto r = test::run(render + " --light-paths " + bad);
    EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("--light-paths"), std::string::npos) << r.output;
  }
}

TEST(LightTracing, CommandLine) { test::expectCommandLine("light", "lite"); }

// The preview renders light tracing pass by pass: its scripted run gives the offline film.
TEST(LightTracing, PreviewEqualsOfflineRender) {
  if (test::run("command -v xvfb-run").exitCode != 0) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string exe = FIRSTSHOT_RENDER_EXE, dir = test::tempDir();
  const std::string common = test::source("scenes/cornell.json") + " --integrator light --width 32 --height 24";
  const auto offline = test::run(exe + " " + common + " --spp 3 -q -o " + dir + "/off.exr");
  ASSERT_EQ(offline.exitCode, 0) << offline.output;
  test::CommandResult preview;
  for (int attempt = 0; attempt < 4; ++attempt) {  // two servers started at once may pick one display: retry
    preview = test::run("env ASAN_OPTIONS=\"${ASAN_OPTIONS}:detect_leaks=0\" xvfb-run -a -s \"-screen 0 1024x768x24\" " +
                        exe + " " + common + " --preview --frames 3 --screenshot " + dir + "/shot.png");
    if (preview.output.find("Xvfb failed to start") == std::string::npos) break;
  }
  ASSERT_EQ(preview.exitCode, 0) << preview.output;
  int w = 0, h = 0;
  std::vector<std::string> channels;
  const auto a = Film::read(dir + "/off.exr", w, h, channels), b = Film::read(dir + "/shot.exr", w, h, channels);
  EXPECT_EQ(a, b);
  EXPECT_GT(*std::max_element(a.begin(), a.end()), 0.0f);
}
