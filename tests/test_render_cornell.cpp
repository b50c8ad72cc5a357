// The Cornell box rendered with NEE only and with first-shot (factors from the preprocessor's
// Embree back end): the image means agree within 3 standard errors, and the per-pixel difference
// shrinks as the patches shrink (the curve is printed).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

SceneDesc cornell() {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 32;
  return desc;
}

FirstShotTable preprocessCornell(const SceneDesc& desc, double patchSize) {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = 256;
  po.settings.patchSize = patchSize;
  po.settings.minPatchSize = patchSize;  // uniform: the test studies the patch size
  po.settings.lightPatchSize = 0.05;
  po.quiet = true;
  return preprocessScene(desc, po);
}

}  // namespace

/// Independent images (different seeds): the means of all three channels agree within 3σ, σ from
/// the per-pixel sample variances of both images.
TEST(CornellFirstShot, ImageMeanAgreesWithNee) {
  const SceneDesc desc = cornell();
  const RenderScene neeScene(desc);
  const RenderScene fsScene(desc, preprocessCornell(desc, desc.settings.patchSize));
  ASSERT_EQ(fsScene.firstShot()->replacedLights.size(), 1u) << "the Cornell light is small";
  IntegratorOptions exact, patch;
  patch.primary = PrimaryMode::Patch;
  const int spp = 64;
  const auto nee = test::renderPath(neeScene, exact, spp, /*seed=*/1);
  const auto fe = test::renderPath(fsScene, exact, spp, /*seed=*/2);
  const auto fp = test::renderPath(fsScene, patch, spp, /*seed=*/3);
  EXPECT_EQ(nee.stats.nonFinite + fe.stats.nonFinite + fp.stats.nonFinite, 0u);
  for (const auto* run : {&fe, &fp}) {
    const char* what = run == &fe ? "--primary exact" : "--primary patch";
    for (int c = 0; c < 3; ++c) {
      double ma, sa, mb, sb;
      test::imageMean(run->film, c, ma, sa);
      test::imageMean(nee.film, c, mb, sb);
      const double se = std::hypot(sa, sb);
      fmt::print("  first-shot {} channel {}: {:.5f} vs NEE {:.5f}, diff {:+.5f} ± {:.5f}\n", what, c, ma, mb, ma - mb, se);
      EXPECT_GT(se, 0.0);
      EXPECT_NEAR(ma, mb, 3 * se) << what << ", channel " << c;
    }
  }
}

/// Paired renders (same camera samples) of NEE and first-shot: the root-mean-square per-pixel bias
/// (noise removed) shrinks with the patch size. Under --primary patch it is dominated by
/// patch-constant shading and blurred shadows at the camera hit; under --primary exact only
/// indirect light is patch-averaged, so its bias is smaller.
TEST(CornellFirstShot, PerPixelDifferenceShrinksWithPatches) {
  FIRSTSHOT_STATISTICS_ONLY("CornellFirstShot.ImageMeanAgreesWithNee");
  const SceneDesc desc = cornell();
  const RenderScene neeScene(desc, 0.025);  // the finest mesh below: paths pair best on the same triangles
  // Pairing needs both integrators to draw the same random numbers: one sample of every light
  // (NEE) and no patch emitters.
  IntegratorOptions exact, patch;
  exact.lightSampler = patch.lightSampler = LightStrategy::All;
  exact.patchNee = patch.patchNee = PatchNee::Off;
  patch.primary = PrimaryMode::Patch;
  auto nee = makeIntegrator("path", exact);
  nee->preprocess(neeScene);
  const Camera camera(desc.camera);
  const int spp = 32;
  const std::vector<double> sizes = {0.1, 0.05, 0.025};
  std::vector<double> biasPatch, biasExact;
  fmt::print("patch size | patches | RMS per-pixel bias, red: --primary patch, --primary exact | paired image-mean bias (exact)\n");
  for (double size : sizes) {
    const RenderScene scene(desc, preprocessCornell(desc, size));
    auto fe = makeIntegrator("path", exact), fp = makeIntegrator("path", patch);
    fe->preprocess(scene);
    fp->preprocess(scene);
    const auto de = test::renderPairedDifference(*nee, *fe, camera, spp, 7, 0);
    const auto dp = test::renderPairedDifference(*nee, *fp, camera, spp, 7, 0);
    biasExact.push_back(de.rmsBias());
    biasPatch.push_back(dp.rmsBias());
    fmt::print("  {:6.3f} m | {:5} | {:.5f}  {:.5f} | {:+.5f} ± {:.5f}\n", size, scene.mesh().size(), biasPatch.back(),
               biasExact.back(), de.imageMean(), de.imageStandardError());
  }
  EXPECT_GT(biasPatch[0], 0.0);
  EXPECT_LT(biasPatch[1], biasPatch[0]);
  EXPECT_LT(biasPatch[2], biasPatch[1]);
  for (size_t i = 0; i < sizes.size(); ++i) EXPECT_LT(biasExact[i], biasPatch[i]);
}
