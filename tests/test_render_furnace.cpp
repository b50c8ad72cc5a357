// White furnace tests of the path tracer: a closed emitting enclosure of albedo ρ shows
// L = Le/(1−ρ) everywhere; with first-shot, a point light inside an integrating sphere gives the
// uniform indirect irradiance ρΦ/(A(1−ρ)) (ρΦ/(4πR²(1−ρ)) for a true sphere).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "tests/render_util.h"

using namespace firstshot;

namespace {

/// A closed enclosure (box or sphere) whose inside emits Le and reflects ρ, seen from inside.
std::string furnaceScene(const std::string& shape, double rho, const std::string& le) {
  const std::string geometry = shape == "box"
      ? R"({"type": "box", "material": "wall", "min": [-1, -1, -1], "max": [1, 1, 1], "flip_normals": true})"
      : R"({"type": "sphere", "material": "wall", "center": [0, 0, 0], "radius": 1, "subdivisions": 2, "flip_normals": true})";
  return fmt::format(R"({{
    "camera": {{"position": [0.1, -0.2, 0.3], "look_at": [0.5, 0.4, -1], "fov_y": 70, "resolution": [32, 32]}},
    "materials": {{"wall": {{"type": "diffuse", "albedo": {}, "emission": {}}}}},
    "shapes": [{}]}})", rho, le, geometry);
}

}  // namespace

class WhiteFurnace : public ::testing::TestWithParam<const char*> {};

TEST_P(WhiteFurnace, RadianceIsLeOverOneMinusRho) {
  struct Case {
    double rho;
    const char* le;
    Color emission;
  };
  for (const Case& c : {Case{0.5, "1", Color(1.0f)}, Case{0.8, "[0.5, 1, 2]", Color(0.5f, 1.0f, 2.0f)}}) {
    SCOPED_TRACE(fmt::format("{} rho={}", GetParam(), c.rho));
    const RenderScene scene(test::sceneFromJson(furnaceScene(GetParam(), c.rho, c.le)));
    IntegratorOptions io;
    io.maxDepth = 100000;  // Russian roulette ends the paths; no truncation bias
    const auto run = test::renderPath(scene, io, 16);
    EXPECT_EQ(run.stats.nonFinite, 0u);
    for (int ch = 0; ch < 3; ++ch) {
      const double expected = c.emission[ch] / (1.0 - c.rho);
      double mean, se;
      test::imageMean(run.film, ch, mean, se);
      fmt::print("  {} rho={} channel {}: {:.5f} ± {:.5f} (expected {:.5f})\n", GetParam(), c.rho, ch, mean, se, expected);
      EXPECT_GT(se, 0.0);
      EXPECT_NEAR(mean, expected, 3 * se) << "channel " << ch << ", standard error " << se;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, WhiteFurnace, ::testing::Values("box", "sphere"));

/// A point light (Φ) off the centre of a closed, non-emitting sphere of albedo ρ, replaced by an
/// exact first-shot table. Full image minus the direct-only image (same seed, so the same camera
/// samples and the same direct term) is the indirect part, whose mean must be ρ/π·E_ind with
/// E_ind = ρΦ/(A(1−ρ)), A the area of the tessellated sphere (energy balance of a closed diffuse
/// enclosure; exactly uniform for a true sphere, nearly so for this one).
TEST(FirstShotFurnace, IntegratingSphereIndirectIrradiance) {
  const double rho = 0.6, phi = 50.0;
  const SceneDesc desc = test::sceneFromJson(test::integratingSphereScene(rho, phi));
  PatchMesh mesh = buildPatches(desc, desc.settings.patchSize);
  const double area = mesh.totalArea();
  ASSERT_NEAR(area, 4 * kPi, 0.02 * 4 * kPi);
  const RenderScene scene(desc, test::pointLightTable(desc, std::move(mesh), 0));
  const double expected = rho / kPi * rho * phi / (area * (1.0 - rho));
  fmt::print("integrating sphere: A = {:.5f} (4πR² = {:.5f}); expected indirect radiance {:.6f}\n", area, 4 * kPi, expected);

  for (PrimaryMode mode : {PrimaryMode::Patch, PrimaryMode::Exact}) {
    SCOPED_TRACE(mode == PrimaryMode::Patch ? "primary patch" : "primary exact");
    IntegratorOptions direct, full;
    direct.primary = full.primary = mode;
    direct.maxDepth = 1;
    full.maxDepth = 100000;
    const int spp = 16;
    const auto d = test::renderPath(scene, direct, spp);
    const auto f = test::renderPath(scene, full, spp);
    EXPECT_EQ(f.stats.nonFinite, 0u);
    // Per-pixel indirect means; their spread over the image gives the standard error (it also
    // contains any real non-uniformity of E_ind, which only makes the bound more lenient).
    const int w = f.film.width(), h = f.film.height();
    double sum = 0, sum2 = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double v = f.film.mean(x, y).x - d.film.mean(x, y).x;
        sum += v, sum2 += v * v;
      }
    const double N = double(w) * h, mean = sum / N;
    const double se = std::sqrt((sum2 / N - mean * mean) / (N - 1));
    fmt::print("  {}: indirect {:.6f} ± {:.6f} (expected {:.6f})\n", mode == PrimaryMode::Patch ? "patch" : "exact", mean, se,
               expected);
    EXPECT_GT(se, 0.0);
    EXPECT_NEAR(mean, expected, 3 * se);
  }
}
