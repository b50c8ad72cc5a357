// Ray-bundle stochastic iteration (render/integrators/bundle/): analytic enclosures, determinism,
// with and without a first-shot table, and the command line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>

#include "common/formats/load_scene.h"
#include "common/patches/patch_size.h"
#include "tests/bundle_util.h"
#include "tests/render_util.h"
#include "tests/stats.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

/// A closed box [−1, 1]³ seen from inside: emitting walls (emitter triangles) or plain walls with a
/// point light, patches of @p patchSize.
std::string boxScene(double rho, const std::string& emission, const std::string& lights, double patchSize) {
  return fmt::format(R"({{
    "camera": {{"position": [0.1, -0.2, 0.3], "look_at": [0.5, 0.4, -1], "fov_y": 70, "resolution": [16, 16]}},
    "materials": {{"wall": {{"type": "diffuse", "albedo": {}{}}}}},
    "shapes": [{{"type": "box", "material": "wall", "min": [-1, -1, -1], "max": [1, 1, 1], "flip_normals": true}}],
    "lights": [{}],
    "settings": {{"patch_size": {}}}}})", rho, emission.empty() ? "" : ", \"emission\": " + emission, lights, patchSize);
}

}  // namespace

/// Every wall of a closed box emits Le and reflects ρ: each element's outgoing radiance, averaged over
/// K iterations, has the expectation startupMean(Le/(1−ρ), ρ, K) (the iteration-k expectation is
/// Le·Σ_{i≤k} ρ^i). Checked per element within 4 batch σ for K and 4K; the error against the limit
/// Le/(1−ρ) and its bound (start-up bias + 4σ) fall with K. The image (camera inside) is checked the same way.
TEST(BundleFurnace, EveryElementConvergesToLeOverOneMinusRho) {
  const double rho = 0.5, le = 1.0, limit = le / (1.0 - rho);
  const RenderScene scene(test::sceneFromJson(boxScene(rho, "1", "", 1.0)));
  IntegratorOptions io;
  double previousError = 0, previousBound = 0;
  for (int K : {32, 128}) {
    auto b = test::makeBundle(scene, io, 64);
    const uint32_t n = b->transfer().elements().size();
    ASSERT_EQ(n, 12u);  // 6 faces × 2 emitter triangles, no patches
    const Camera camera(scene.desc().camera);
    Film film(camera.width(), camera.height());
    std::vector<std::vector<double>> outgoing(n);
    std::vector<double> imageMeans;
    for (int k = 0; k < K; ++k) {
      Film one(camera.width(), camera.height());
      RenderOptions ro;
      ro.spp = 1, ro.firstSample = k, ro.seed = 7;
      render(*b, camera, one, ro);
      for (uint32_t e = 0; e < n; ++e) outgoing[e].push_back(b->transfer().outgoing(e, 0).y);  // side 0 faces inwards
      double m, se;
      test::imageMean(one, 1, m, se);
      imageMeans.push_back(m);
    }
    const double expected = test::startupMean(limit, rho, K);
    double worstError = 0, worstBound = 0;
    for (uint32_t e = 0; e < n; ++e) {
      const test::BatchMean bm = test::batchMean(outgoing[e]);
      EXPECT_GT(bm.se, 0.0);
      EXPECT_NEAR(bm.mean, expected, 4 * bm.se + 1e-9) << "element " << e << ", K = " << K;
      worstError = std::max(worstError, std::abs(bm.mean - limit));
      worstBound = std::max(worstBound, (limit - expected) + 4 * bm.se);
    }
    const test::BatchMean img = test::batchMean(imageMeans);
    fmt::print("furnace K={}: expected mean {:.5f} (limit {:.5f}); worst |error| {:.5f}, bound {:.5f}; image {:.5f} ± {:.5f}\n",
               K, expected, limit, worstError, worstBound, img.mean, img.se);
    EXPECT_NEAR(img.mean, expected, 4 * img.se) << "K = " << K;
    EXPECT_LE(worstError, worstBound);
    if (previousError > 0) {
      EXPECT_LT(worstError, 0.6 * previousError);
      EXPECT_LT(worstBound, 0.6 * previousBound);
    }
    previousError = worstError, previousBound = worstBound;
  }
}

/// A point light (Φ) off the centre of a closed box of albedo ρ, replaced by an exact first-shot
/// table: the indirect irradiance 2π·I_k(j) (what the bundle brings; for a diffuse patch L_r = ρ/π·E),
/// area-averaged over the patches, has the limit ρΦ/(A(1−ρ)) (energy balance of a closed enclosure:
/// all of Φ lands on the walls, ρ of each bounce is re-emitted) and the same start-up factor as above.
TEST(BundleFurnace, IntegratingCubeIndirectIrradiance) {
  const double rho = 0.6, phi = 40.0;
  const SceneDesc desc = test::sceneFromJson(boxScene(rho, "", R"({"type": "point", "position": [0.3, 0.25, -0.1], "power": 40})", 0.5));
  PatchMesh mesh = buildPatches(desc, resolvePatchSize(desc));
  const double area = mesh.totalArea();
  ASSERT_NEAR(area, 24.0, 1e-6);
  const RenderScene scene(desc, test::pointLightTable(desc, std::move(mesh), 0));
  IntegratorOptions io;
  auto b = test::makeBundle(scene, io, 96);
  const int K = 128;
  const uint32_t n = scene.mesh().size();
  std::vector<double> average;
  std::vector<double> perPatch(n, 0.0);
  for (int k = 0; k < K; ++k) {
    b->beginPass(k, 3);
    double sum = 0;
    for (uint32_t j = 0; j < n; ++j) {
      const double e = 2 * kPi * b->transfer().incoming(j, 0).x;
      sum += e * scene.mesh().patches[j].area;
      perPatch[j] += e / K;
    }
    average.push_back(sum / area);
  }
  const double limit = rho * phi / (area * (1.0 - rho)), expected = test::startupMean(limit, rho, K);
  const test::BatchMean bm = test::batchMean(average);
  const auto [lo, hi] = std::minmax_element(perPatch.begin(), perPatch.end());
  fmt::print("integrating cube: average indirect irradiance {:.5f} ± {:.5f} (expected {:.5f}, limit {:.5f}); "
             "per patch {:.4f} .. {:.4f}\n", bm.mean, bm.se, expected, limit, *lo, *hi);
  EXPECT_GT(bm.se, 0.0);
  EXPECT_NEAR(bm.mean, expected, 4 * bm.se);
  // A cube's indirect irradiance is not exactly uniform (the bright first bounce of the nearest wall,
  // darker corners), but every patch stays within ±40% of the average.
  EXPECT_GT(*lo, 0.6 * expected);
  EXPECT_LT(*hi, 1.4 * expected);
}

/// The same box and light without the table (the plain algorithm: the light sends two lines per
/// iteration) and with it converge to the same image: with --primary exact both take the same NEE
/// samples at camera-visible points, and their global parts have the same expectation (both are patch
/// averages of the same direct irradiance). Compared per 8×8 block within 4.5 σ of the difference.
TEST(BundleFirstShot, WithAndWithoutTableConvergeToTheSameImage) {
  const double rho = 0.6;
  const SceneDesc desc = test::sceneFromJson(boxScene(rho, "", R"({"type": "point", "position": [0.3, 0.25, -0.1], "power": 40})", 0.5));
  const RenderScene plain(desc);
  const RenderScene table(desc, test::pointLightTable(desc, buildPatches(desc, resolvePatchSize(desc)), 0));
  IntegratorOptions io;
  const Camera camera(desc.camera);
  const int K = 128, w = camera.width(), h = camera.height();
  Film fa(w, h), fb(w, h);
  const auto a = test::iterationImages(*test::makeBundle(plain, io, 96), camera, K, 0, fa, 5);
  const auto t = test::iterationImages(*test::makeBundle(table, io, 96), camera, K, 0, fb, 6);
  for (int by = 0; by < h; by += 8)
    for (int bx = 0; bx < w; bx += 8) {
      const auto sa = test::batchMean(test::blockSeries(a, w, bx, by, bx + 8, by + 8));
      const auto st = test::batchMean(test::blockSeries(t, w, bx, by, bx + 8, by + 8));
      const double se = std::hypot(sa.se, st.se);
      fmt::print("block ({},{}): without table {:.5f} ± {:.5f}, with table {:.5f} ± {:.5f}\n", bx, by, sa.mean, sa.se, st.mean,
                 st.se);
      EXPECT_GT(se, 0.0);
      EXPECT_NEAR(sa.mean, st.mean, 4.5 * se) << "block " << bx << "," << by;
    }
}

/// The state and the image are bit-identical for 1 and 2 threads (and with a table, --primary patch).
TEST(BundleDeterminism, SameImageForOneAndTwoThreads) {
  const SceneDesc desc = test::sceneFromJson(boxScene(0.6, "", R"({"type": "point", "position": [0.3, 0.25, -0.1], "power": 40})", 0.5));
  const RenderScene table(desc, test::pointLightTable(desc, buildPatches(desc, resolvePatchSize(desc)), 0));
  SceneDesc small = loadScene(test::source("scenes/cornell.json"));
  small.camera.width = small.camera.height = 24;
  const RenderScene cornell(small, 0.1);
  for (const RenderScene* scene : {&cornell, &table}) {
    for (PrimaryMode mode : {PrimaryMode::Exact, PrimaryMode::Patch}) {
      IntegratorOptions io;
      io.primary = mode;
      auto one = test::makeBundle(*scene, io, 64), two = test::makeBundle(*scene, io, 64);
      const test::RenderRun r1 = test::renderWith(*one, *scene, 5, 1, 1), r2 = test::renderWith(*two, *scene, 5, 1, 2);
      EXPECT_EQ(r1.stats.nonFinite, 0u);
      for (uint32_t e = 0; e < one->transfer().elements().size(); ++e)
        for (int s = 0; s < 2; ++s) ASSERT_EQ(one->transfer().incoming(e, s), two->transfer().incoming(e, s));
      for (int y = 0; y < r1.film.height(); ++y)
        for (int x = 0; x < r1.film.width(); ++x) ASSERT_EQ(r1.film.mean(x, y), r2.film.mean(x, y)) << x << "," << y;
    }
  }
}

/// Restarting at sample index 0 restarts the state: the same iteration gives the same state.
TEST(BundleDeterminism, RestartReproducesTheState) {
  const RenderScene scene(loadScene(test::source("scenes/cornell.json")), 0.1);
  IntegratorOptions io;
  auto b = test::makeBundle(scene, io, 32);
  b->beginPass(0, 9);
  b->beginPass(1, 9);
  b->beginPass(2, 9);
  const auto state = [&] {
    std::vector<Color> s;
    for (uint32_t e = 0; e < b->transfer().elements().size(); ++e) s.push_back(b->transfer().incoming(e, 0));
    return s;
  };
  const std::vector<Color> third = state();
  b->beginPass(0, 9);
  EXPECT_NE(state(), third);
  b->beginPass(2, 9);  // catches up from iteration 0
  EXPECT_EQ(state(), third);
}

TEST(BundleCli, RendersAndRejectsBadValues) {
  const std::string dir = test::tempDir(), render = FIRSTSHOT_RENDER_EXE, scene = test::source("scenes/cornell.json");
  const std::string base = render + " " + scene + " --integrator bundle --width 8 --height 8 -q";
  const auto ok = test::run(base + " --iterations 2 --bundle-resolution 16 --bundle-directions halton -o " + dir + "/b.exr");
  EXPECT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/b.exr"));
  struct Bad {
    std::string args, message;
  };
  for (const Bad& bad : {Bad{" --bundle-resolution 0", "--bundle-resolution"}, Bad{" --bundle-resolution -3", "between 1 and"},
                         Bad{" --bundle-directions sobolev", "expected random or halton"},
                         Bad{" --iterations 0", "at least 1"}, Bad{" --iterations 2 --spp 2", "one of --iterations"}}) {
    const auto r = test::run(base + bad.args + " -o " + dir + "/x.exr");
    EXPECT_EQ(r.exitCode, 2) << bad.args << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(bad.message)) << bad.args;
  }
  const auto other = test::run(render + " " + scene + " --integrator path --bundle-resolution 8 --width 8 --height 8 -q -o " +
                               dir + "/y.exr");
  EXPECT_EQ(other.exitCode, 2);
  EXPECT_THAT(other.output, HasSubstr("--bundle-resolution: not used by --integrator path (used by: bundle)"));
}

/// One all-hits query per line (EmbreeScene::allHits) finds the same crossings as successive
/// closest hits: after a few iterations on Cornell the states agree (all but a handful of slots
/// exactly; hits closer together than the successive-hit offset may differ).
TEST(BundleTraversal, AllHitsAgreesWithSuccessiveHits) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  const RenderScene scene(desc, 0.1);
  IntegratorOptions io;
  BundleIntegrator successive(io), all(io);
  BundleSettings s;
  s.resolution = 96;
  successive.setSettings(s);
  s.allHits = true;
  all.setSettings(s);
  successive.preprocess(scene);
  all.preprocess(scene);
  successive.beginPass(3, 1);
  all.beginPass(3, 1);
  size_t equal = 0, slots = 0;
  double sumA = 0, sumB = 0;
  for (uint32_t e = 0; e < successive.transfer().elements().size(); ++e)
    for (int side = 0; side < 2; ++side, ++slots) {
      const Color a = successive.transfer().incoming(e, side), b = all.transfer().incoming(e, side);
      equal += a == b;
      sumA += a.x, sumB += b.x;
    }
  fmt::print("all hits vs successive hits: {} of {} slots equal, totals {:.6f} vs {:.6f}\n", equal, slots, sumA, sumB);
  EXPECT_GE(double(equal), 0.99 * double(slots));
  EXPECT_NEAR(sumA, sumB, 1e-3 * sumA);
}

/// The global directions are uniform on the sphere for both sequences: the moments E[ω] = 0 and
/// E[ω_i²] = 1/3 over 4096 iterations, within 4σ for the random ones (σ from the samples) and
/// much tighter for the Halton points (low discrepancy: error ~ log²N/N).
TEST(BundleDirections, UniformOnTheSphere) {
  for (BundleDirections kind : {BundleDirections::Random, BundleDirections::Halton}) {
    const int n = 4096;
    std::vector<test::RunningStats> first(3), second(3);
    for (int k = 0; k < n; ++k) {
      const Vec3 w = bundleDirection(kind, 5, uint64_t(k));
      ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
      for (int a = 0; a < 3; ++a) first[a].add(w[a]), second[a].add(double(w[a]) * w[a]);
    }
    for (int a = 0; a < 3; ++a) {
      const double tol1 = kind == BundleDirections::Random ? 4 * first[a].standardError() : 0.005;
      const double tol2 = kind == BundleDirections::Random ? 4 * second[a].standardError() : 0.005;
      EXPECT_NEAR(first[a].mean, 0.0, tol1) << "axis " << a;
      EXPECT_NEAR(second[a].mean, 1.0 / 3.0, tol2) << "axis " << a;
    }
  }
}
