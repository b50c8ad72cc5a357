// The hard-case suite (tests/hard_cases/, docs/robustness.md "Hard cases"): each scene goes through
// the tools' pipeline (preprocess → .fsd → render with the path tracer and the irradiance cache)
// and must give a finite table, a finite image and the right value: per-patch factors against the
// closed forms, images against analytic radiance, a furnace's Le·(D+1), scaled scenes against the
// unit scene within σ from the samples. The cases that must be refused are in
// test_hard_cases_errors.cpp.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/lights/form_factors.h"
#include "tests/bundle_util.h"
#include "tests/hard_cases.h"

using namespace firstshot;

namespace {

/// Sum of patch @p j's factors from light sample @p sample.
double tableFactor(const FirstShotTable& t, uint32_t j, uint32_t sample) {
  double r = 0;
  for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k)
    if (t.sampleIndex[k] == sample) r += t.factor[k];
  return r;
}

/// r_j = Ω_j / (4π A_j) of a point light at @p light over patch @p p, seen whole.
double pointFactor(const Patch& p, const Vec3d& light) {
  std::vector<Vec3d> poly;
  for (uint32_t k = 0; k < p.count; ++k) poly.emplace_back(p.v[k]);
  return analytic::solidAnglePolygon(light, poly) / (4.0 * kPi * p.area);
}

/// Largest |table − closed form| over the patches, relative to the largest closed-form factor, for
/// the single point light of a scene in which it sees every patch whole (convex room, open plane).
double worstPointFactorError(const SceneDesc& desc, const FirstShotTable& t) {
  const Vec3d light = desc.lights[0].position;
  double worst = 0, largest = 0;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) largest = std::max(largest, pointFactor(t.mesh.patches[j], light));
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const double expected = pointFactor(t.mesh.patches[j], light), got = tableFactor(t, j, 0);
    worst = std::max(worst, std::abs(got - expected) / largest);
  }
  return worst;
}

/// Renders @p scene with both integrators at @p spp and checks that every pixel is finite.
std::vector<test::RenderRun> renderFinite(const RenderScene& scene, const IntegratorOptions& io, int spp) {
  std::vector<test::RenderRun> runs;
  for (const char* name : test::kHardCaseIntegrators) {
    SCOPED_TRACE(name);
    runs.push_back(test::renderNamed(name, scene, io, spp));
    test::expectFiniteImage(runs.back());
  }
  return runs;
}

}  // namespace

/// Point lights that see every patch whole: 1e-4 m from the floor of a box, in the plane of a floor
/// (grazing the floor, lighting a wall), over 1e-6 m² patches, inside an albedo-0 and an albedo-1 box.
class PointLightCase : public ::testing::TestWithParam<const char*> {};

TEST_P(PointLightCase, TableMatchesClosedFormsAndImagesAreFinite) {
  const SceneDesc desc = test::loadHardCase(GetParam());
  const FirstShotTable table = test::hardCaseTable(desc);
  test::expectFiniteTable(table);
  const double error = worstPointFactorError(desc, table);
  fmt::print("{}: {} patches, worst |r - Ω/(4πA)| / max r = {:.2e}\n", GetParam(), table.mesh.size(), error);
  EXPECT_LT(error, 1e-4) << "the analytic estimator is exact to float rounding for patches seen whole";
  const RenderScene scene(desc, table);
  renderFinite(scene, test::sceneOptions(desc), 4);
}

INSTANTIATE_TEST_SUITE_P(HardCases, PointLightCase,
                         ::testing::Values("point_near_wall.json", "light_coplanar.json", "tiny_patches.json",
                                           "albedo0_box.json", "albedo1_box_point.json"),
                         [](const auto& p) {
                           std::string s = p.param;
                           return s.substr(0, s.find('.'));
                         });

/// The point light 1e-4 m from the floor: the patch under it receives half the light's power
/// (Ω → 2π), E = Φ/(2A), and the rest of the floor almost none.
TEST(HardCases, PointNearWallPatchBelowGetsHalfThePower) {
  const SceneDesc desc = test::loadHardCase("point_near_wall.json");
  const FirstShotTable t = test::hardCaseTable(desc);
  const Vec3d light = desc.lights[0].position;
  double total = 0;
  int belowCount = 0;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const Patch& p = t.mesh.patches[j];
    const double power = tableFactor(t, j, 0) * p.area;  // fraction of Φ on patch j
    total += power;
    const bool below = p.normal.y > 0.5f && std::abs(p.centroid.x - light.x) < 0.1 && std::abs(p.centroid.z - light.z) < 0.1;
    if (below) {
      fmt::print("point near wall: patch {} under the light gets {:.6f} of the power (expected 0.5 − O(d/a))\n", j, power);
      EXPECT_NEAR(power, 0.5, 1e-3) << "patch " << j;
    }
    belowCount += below;
  }
  EXPECT_EQ(belowCount, 1) << "one patch lies under the light";
  fmt::print("point near wall: the box receives {:.6f} of the power\n", total);
  EXPECT_NEAR(total, 1.0, 1e-4) << "a closed box receives all of the light's power";
}

/// Directional light 0.5° above the floor's plane: every floor patch has r = cos θ (89.5°), and the
/// image of the floor (camera looking down, nothing else in view) is ρ/π·E⊥·cos θ.
TEST(HardCases, GrazingDirectionalLight) {
  const SceneDesc desc = test::loadHardCase("grazing_light.json");
  const FirstShotTable t = test::hardCaseTable(desc);
  test::expectFiniteTable(t);
  const double cosTheta = -glm::normalize(desc.lights[0].direction).y;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) EXPECT_NEAR(tableFactor(t, j, 0), cosTheta, 1e-3 * cosTheta) << "patch " << j;
  const double expected = 0.5 / kPi * desc.lights[0].irradiance.x * cosTheta;
  const RenderScene scene(desc, t);
  IntegratorOptions exact = test::sceneOptions(desc), patch = exact;
  patch.primary = PrimaryMode::Patch;
  for (const IntegratorOptions& io : {exact, patch}) {
    const auto runs = renderFinite(scene, io, 4);
    for (size_t i = 0; i < runs.size(); ++i) {
      const test::MeanSe m = test::channelMean(runs[i].film, 0);
      fmt::print("grazing light, {} ({}): {:.6f} ± {:.6f}, expected {:.6f}\n", test::kHardCaseIntegrators[i],
                 io.primary == PrimaryMode::Patch ? "patch" : "exact", m.mean, m.se, expected);
      EXPECT_NEAR(m.mean, expected, 3 * m.se + 1e-3 * expected) << test::kHardCaseIntegrators[i];
    }
  }
}

/// Albedo-0 walls around an albedo-0.5 floor: no light comes back to the floor, so the image is the
/// direct light alone, ρ/π·Φ cos θ/(4π d²) where a pixel sees the floor and 0 elsewhere.
TEST(HardCases, AlbedoZeroBoxIsDirectLightOnly) {
  const SceneDesc desc = test::loadHardCase("albedo0_box.json");
  const RenderScene scene(desc, test::hardCaseTable(desc));
  const Camera camera(desc.camera);
  const Vec3d light = desc.lights[0].position;
  const double phi = desc.lights[0].power.x, floorY = 0;
  auto direct = [&](const Ray& r) {
    const Vec3d o(r.o), d(r.d);
    if (d.y >= 0) return 0.0;
    const double t = (floorY - o.y) / d.y;
    const double tx = d.x > 0 ? (2 - o.x) / d.x : (d.x < 0 ? -o.x / d.x : 1e30);
    const double tz = d.z > 0 ? (1 - o.z) / d.z : (d.z < 0 ? -o.z / d.z : 1e30);
    if (t > std::min(tx, tz)) return 0.0;  // a wall first
    const Vec3d p = o + t * d, toLight = light - p;
    const double d2 = glm::dot(toLight, toLight);
    return 0.5 / kPi * phi / (4 * kPi) * (toLight.y / std::sqrt(d2)) / d2;
  };
  std::vector<double> expected;
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x) expected.push_back(test::footprintAverage(camera, x, y, direct, 16));
  const auto runs = renderFinite(scene, test::sceneOptions(desc), 16);
  for (size_t i = 0; i < runs.size(); ++i) {
    const test::Comparison c = test::compareImage(runs[i].film, expected, 0, 4);
    fmt::print("albedo-0 box, {}: mean {:.6f} (expected {:.6f}, se {:.6f}), worst 4x4 block z {:.2f}\n",
               test::kHardCaseIntegrators[i], c.meanExpected + c.meanDiff, c.meanExpected, c.se, c.worstBlockZ);
    EXPECT_LT(std::abs(c.meanDiff), 3 * c.se + 1e-4 * c.meanExpected) << test::kHardCaseIntegrators[i];
    EXPECT_LT(c.worstBlockZ, 4.0) << test::kHardCaseIntegrators[i];
  }
}

/// A closed, emitting box of albedo 1: nothing leaves, so radiance grows by Le per bounce; at
/// max_depth D the path tracer must give Le·(D+1) and stop. With no depth limit Russian roulette
/// (survival at most 0.95) still ends every path, and the irradiance cache finishes too.
TEST(HardCases, AlbedoOneBoxStopsAtMaxDepth) {
  const SceneDesc desc = test::loadHardCase("albedo1_box.json");
  const RenderScene scene(desc, test::hardCaseTable(desc));
  const IntegratorOptions io = test::sceneOptions(desc);
  const auto runs = renderFinite(scene, io, 8);
  const test::MeanSe path = test::channelMean(runs[0].film, 0);
  const double expected = 1.0 * (io.maxDepth + 1);
  fmt::print("albedo-1 box, path, max depth {}: {:.4f} ± {:.4f}, expected {:.4f}; irradiance cache {:.4f}\n", io.maxDepth,
             path.mean, path.se, expected, test::channelMean(runs[1].film, 0).mean);
  EXPECT_NEAR(path.mean, expected, 3 * path.se + 1e-6);
  IntegratorOptions unbounded;
  unbounded.maxDepth = 1000000;
  for (const char* name : test::kHardCaseIntegrators) {
    SCOPED_TRACE(name);
    const auto run = test::renderNamed(name, scene, unbounded, 2);
    test::expectFiniteImage(run);
    EXPECT_GT(test::channelMean(run.film, 0).mean, expected) << "more bounces, more light";
  }
  // Stochastic iteration keeps light by bounce order up to max depth 16 (docs/bundle.md): with albedo 1
  // its estimate grows with the iterations until they reach max depth, and every iteration ends finite.
  const auto bundle = test::makeBundle(scene, io, 32);
  for (int K : {8, 32}) {
    const auto run = test::renderWith(*bundle, scene, K);
    test::expectFiniteImage(run);
    fmt::print("albedo-1 box, bundle, {} iterations: {:.3f}\n", K, test::channelMean(run.film, 0).mean);
  }
}

/// The same scene at 1e-3 and 1e4 times the size, the power scaled with the area: radiance is
/// scale-invariant, so each image's mean (per channel) and every 4×4 block must match the unit
/// scene's within 4σ of the difference (σ from both images' samples), and so must the fraction of
/// the light's power the table puts on the patches.
TEST(HardCases, ScaledScenesGiveTheUnitImage) {
  struct Render {
    double power = 0;
    std::vector<test::RenderRun> runs;
  };
  auto run = [](const char* file) {
    const SceneDesc desc = test::loadHardCase(file);
    const FirstShotTable t = test::hardCaseTable(desc);
    test::expectFiniteTable(t);
    Render r;
    for (uint32_t j = 0; j < t.mesh.size(); ++j) r.power += tableFactor(t, j, 0) * t.mesh.patches[j].area;
    const RenderScene scene(desc, t);
    r.runs = renderFinite(scene, test::sceneOptions(desc), 16);
    return r;
  };
  const Render unit = run("scale_unit.json");
  for (const char* file : {"scale_1e-3.json", "scale_1e4.json"}) {
    SCOPED_TRACE(file);
    const Render scaled = run(file);
    EXPECT_NEAR(scaled.power, unit.power, 1e-4 * unit.power) << "fraction of the power on the patches";
    for (size_t i = 0; i < scaled.runs.size(); ++i) {
      const Film &a = unit.runs[i].film, &b = scaled.runs[i].film;
      for (int c = 0; c < 3; ++c) {
        const test::MeanSe ma = test::channelMean(a, c), mb = test::channelMean(b, c);
        const double sigma = std::hypot(ma.se, mb.se);
        if (c == 0)
          fmt::print("{}, {}: mean {:.5f} vs unit {:.5f} (σ {:.5f})\n", file, test::kHardCaseIntegrators[i], mb.mean, ma.mean, sigma);
        EXPECT_NEAR(mb.mean, ma.mean, 4 * sigma + 1e-6) << test::kHardCaseIntegrators[i] << ", channel " << c;
        for (int by = 0; by < a.height(); by += 4)
          for (int bx = 0; bx < a.width(); bx += 4) {
            double d = 0, v = 0;
            for (int y = by; y < by + 4; ++y)
              for (int x = bx; x < bx + 4; ++x) {
                d += b.mean(x, y)[c] - a.mean(x, y)[c];
                v += a.variance(x, y)[c] / a.samples(x, y) + b.variance(x, y)[c] / b.samples(x, y);
              }
            EXPECT_LE(std::abs(d), 4.5 * std::sqrt(v) + 1e-6 * 16)
                << test::kHardCaseIntegrators[i] << ", channel " << c << ", block " << bx << ", " << by;
          }
      }
    }
  }
}
