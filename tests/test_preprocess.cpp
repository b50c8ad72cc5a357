// The preprocessor end to end: first-shot factors against analytic values, flux conservation,
// the hard cases, back-end agreement and thread independence.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "preprocess/preprocessor.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

SceneDesc sceneFrom(const std::string& json) { return test::sceneFromJson(json); }

FirstShotTable run(const SceneDesc& s, int R, const std::string& backend = "gl", double lightPatch = 0, int threads = 2) {
  PreprocessOptions o = defaultOptions(s);
  o.settings.resolution = R;
  o.settings.backend = backend;
  o.settings.minPatchSize = o.settings.patchSize;  // a uniform mesh: these tests compare estimators and back ends on one mesh
  if (lightPatch > 0) o.settings.lightPatchSize = lightPatch;
  o.threads = threads;
  o.quiet = true;
  return preprocessScene(s, o);
}

/// Σ_i r_ij over the samples of patch j (one light: the patch's irradiance per unit emission).
double rowSum(const FirstShotTable& t, uint32_t j) {
  double s = 0;
  for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k) s += t.factor[k];
  return s;
}

/// Σ_j E_j A_j / Σ emission: the fraction of the emitted flux the patches receive (per unit emission).
double capturedFlux(const FirstShotTable& t) {
  double sum = 0;
  for (uint32_t j = 0; j < t.mesh.size(); ++j)
    for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k) sum += double(t.factor[k]) * t.mesh.patches[j].area;
  return sum;
}

std::string closedBox(const std::string& lights, const std::string& extraShapes = "", double patch = 0.25) {
  return R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": 1}},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [2,1.5,1], "flip_normals": true})" +
         extraShapes + R"(], "lights": [)" + lights + R"(], "settings": {"patch_size": )" + std::to_string(patch) + "}}";
}

}  // namespace

/// Width in pixels of a patch seen from @p eye on the cube face of its centroid's dominant axis at
/// resolution R: √(projected area) / pixel size.
double widthInPixels(const Patch& p, const Vec3d& eye, int R) {
  const Vec3d c = Vec3d(p.centroid) - eye;
  const Vec3d a = glm::abs(c);
  const int major = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = (major + 1) % 3, v = (major + 2) % 3;
  double area2 = 0;
  Vec2d q[4];
  for (uint32_t k = 0; k < p.count; ++k) {
    const Vec3d d = Vec3d(p.v[k]) - eye;
    q[k] = Vec2d(d[u], d[v]) / std::abs(d[major]);
  }
  for (uint32_t k = 0; k < p.count; ++k) area2 += q[k].x * q[(k + 1) % p.count].y - q[(k + 1) % p.count].x * q[k].y;
  return std::sqrt(std::abs(area2) / 2) / (2.0 / R);
}

// Point light over a plane of patches: r_ij against Ω_j/(4π A_j), at R = 512. The plain pixel sums
// show the aliasing law of REFERENCE.md; the analytic estimator must stay within 0.5% for every patch
// at least 10 pixels wide.
TEST(Preprocess, PointLightOverPlaneMatchesSolidAngle) {
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}], "settings": {"patch_size": 0.1}})");
  const Vec3d eye(0, 1, 0);
  for (const char* backend : {"gl", "embree"}) {
    for (const char* estimator : {"pixels", "analytic"}) {
      struct Bin {
        double sumSq = 0, max = 0;
        int n = 0;
      };
      std::map<int, Bin> bins;  // by patch width in pixels, [2^k, 2^(k+1))
      for (double patchSize : {0.2, 0.1, 0.05, 0.025, 0.0125}) {
        SCOPED_TRACE(std::string(backend) + " " + estimator + " " + std::to_string(patchSize));
        PreprocessOptions o = defaultOptions(s);
        o.settings.resolution = 512, o.settings.backend = backend, o.settings.estimator = estimator, o.quiet = true;
        o.settings.patchSize = patchSize;
        const FirstShotTable t = preprocessScene(s, o);
        ASSERT_EQ(t.samples.size(), 1u);
        for (uint32_t j = 0; j < t.mesh.size(); ++j) {
          const Patch& p = t.mesh.patches[j];
          const std::vector<Vec3d> poly = {Vec3d(p.v[0]), Vec3d(p.v[1]), Vec3d(p.v[2]), Vec3d(p.v[3])};
          const double exact = analytic::solidAnglePolygon(eye, poly) / (4 * kPi * p.area);
          const double rel = std::abs(rowSum(t, j) - exact) / exact;
          const double widthPx = widthInPixels(p, eye, 512);
          Bin& b = bins[int(std::floor(std::log2(widthPx)))];
          b.sumSq += rel * rel, b.max = std::max(b.max, rel), ++b.n;
          if (std::string(estimator) == "analytic" && widthPx >= 10) {
            EXPECT_LE(rel, 0.005) << "patch " << j << ", " << widthPx << " px";
          }
        }
      }
      std::printf("[%s, %s] patch width (px) | patches | max rel. error | RMS rel. error\n", backend, estimator);
      for (const auto& [k, b] : bins)
        std::printf("  %3d-%3d px | %5d | %.5f | %.5f\n", 1 << k, 2 << k, b.n, b.max, std::sqrt(b.sumSq / b.n));
    }
  }
}

// Area light over a parallel patch: Σ_i Le·r_ij → π·Le·F, converging as the light is tessellated.
TEST(Preprocess, AreaLightOverParallelPatchConverges) {
  // A 1×1 emitter facing down at height 1 over a 1×1 receiver (a single patch).
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": 2}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[0,0,1],[1,0,1],[1,0,0]]},
               {"type": "quad", "material": "lamp", "vertices": [[0,1,0],[1,1,0],[1,1,1],[0,1,1]]}],
    "settings": {"patch_size": 2, "small_light_max_solid_angle": 10}})");
  const double exact = kPi * 2.0 * analytic::parallelRectanglesFormFactor(1, 1, 1);
  EXPECT_NEAR(analytic::parallelRectanglesFormFactor(1, 1, 1), 0.1998249, 1e-7);
  double previous = 1e9;
  for (double lp : {1.0, 0.5, 0.25, 0.125}) {
    const FirstShotTable t = run(s, 256, "gl", lp);
    ASSERT_EQ(t.mesh.size(), 1u);
    const double e = t.irradiance(0).x;
    const double err = std::abs(e - exact) / exact;
    std::printf("light tessellation %.3f m: %zu samples, E = %.6f, exact %.6f, rel. error %.5f\n", lp, t.samples.size(), e, exact, err);
    EXPECT_LT(err, previous);
    previous = err;
  }
  EXPECT_LT(previous, 0.005);
}

// A point light in a closed box: Σ_j E_j A_j = Φ within 0.1%.
TEST(Preprocess, PointLightInClosedBoxConservesFlux) {
  const SceneDesc s = sceneFrom(closedBox(R"({"type": "point", "position": [0.7, 0.9, 0.4], "power": 5})"));
  for (const char* backend : {"gl", "embree"}) {
    const FirstShotTable t = run(s, 256, backend);
    EXPECT_NEAR(capturedFlux(t), 1.0, 1e-3) << backend;
    double flux = 0;
    for (uint32_t j = 0; j < t.mesh.size(); ++j) flux += t.irradiance(j).x * t.mesh.patches[j].area;
    EXPECT_NEAR(flux, 5.0, 5e-3) << backend;
  }
}

// A spot light in a closed box delivers its whole power Φ (the profile is normalised).
TEST(Preprocess, SpotLightInClosedBoxConservesFlux) {
  const SceneDesc s = sceneFrom(closedBox(
      R"({"type": "spot", "position": [1, 1.2, 0.5], "direction": [0.3, -1, 0.1], "power": 3, "inner_angle": 20, "outer_angle": 35})"));
  const FirstShotTable t = run(s, 256);
  EXPECT_NEAR(capturedFlux(t), 1.0, 2e-3);
}

// An area light coplanar with the ceiling of a closed box (no offset): the light's flux π·Le·A
// reaches the room; the ceiling around it neither z-fights nor leaks.
TEST(Preprocess, AreaLightCoplanarWithWall) {
  const SceneDesc s = sceneFrom(closedBox("", R"(, {"type": "quad", "material": "lamp", "small": true,
      "vertices": [[0.8,1.5,0.3],[1.2,1.5,0.3],[1.2,1.5,0.7],[0.8,1.5,0.7]]})"));
  const FirstShotTable t = run(s, 256, "gl", 0.05);
  double toCeiling = 0, total = 0;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const double f = t.irradiance(j).x * t.mesh.patches[j].area;
    total += f;
    if (t.mesh.patches[j].normal.y < -0.99f) toCeiling += f;
  }
  const double phi = kPi * 1.0 * 0.4 * 0.4;
  EXPECT_NEAR(total, phi, 5e-3 * phi);
  EXPECT_EQ(toCeiling, 0.0);
}

// A patch 1e-4 m from a point light still receives its solid angle.
TEST(Preprocess, PatchVeryCloseToPointLight) {
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-0.001,0,-0.001],[-0.001,0,0.001],[0.001,0,0.001],[0.001,0,-0.001]]},
               {"type": "quad", "material": "m", "vertices": [[-1,-1,-1],[-1,-1,1],[1,-1,1],[1,-1,-1]]}],
    "lights": [{"type": "point", "position": [0, 0.0001, 0], "power": 1}], "settings": {"patch_size": 1}})");
  for (const char* backend : {"gl", "embree"}) {
    const FirstShotTable t = run(s, 512, backend);
    const Patch& p = t.mesh.patches[0];
    const std::vector<Vec3d> poly = {Vec3d(p.v[0]), Vec3d(p.v[1]), Vec3d(p.v[2]), Vec3d(p.v[3])};
    const double exact = analytic::solidAnglePolygon(Vec3d(0, 1e-4, 0), poly) / (4 * kPi * p.area);
    EXPECT_NEAR(rowSum(t, 0), exact, 2e-3 * exact) << backend;
  }
}

// A patch seen edge-on (its plane contains the light) gets nothing, and nothing leaks past it.
TEST(Preprocess, PatchSeenEdgeOn) {
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0.2,0,-0.5],[0.2,0,0.5],[0.2,1,0.5],[0.2,1,-0.5]]},
               {"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
    "lights": [{"type": "point", "position": [0.2, 0.5, 0], "power": 1}], "settings": {"patch_size": 2}})");
  const FirstShotTable t = run(s, 256);
  EXPECT_LT(rowSum(t, 0), 1e-3 * rowSum(t, 1));
  // The floor behind the edge-on wall is lit on both sides: its factor matches the full solid angle.
  const Patch& f = t.mesh.patches[1];
  const std::vector<Vec3d> poly = {Vec3d(f.v[0]), Vec3d(f.v[1]), Vec3d(f.v[2]), Vec3d(f.v[3])};
  const double exact = analytic::solidAnglePolygon(Vec3d(0.2, 0.5, 0), poly) / (4 * kPi * f.area);
  EXPECT_NEAR(rowSum(t, 1), exact, 5e-3 * exact);
}

// Patches smaller than a pixel (docs/firstshot-format.md). The pixel sums give each one 0 or a whole
// pixel's worth, right only summed over a region (up to the aliasing of its outline); the analytic
// estimator gives each its exact share (closed form × the visible fraction of points on it).
TEST(Preprocess, PatchesSmallerThanAPixel) {
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-0.5,0,-0.5],[-0.5,0,0.5],[0.5,0,0.5],[0.5,0,-0.5]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}], "settings": {"patch_size": 0.002}})");
  for (const char* estimator : {"pixels", "analytic"}) {
    PreprocessOptions o = defaultOptions(s);
    o.settings.resolution = 256, o.settings.estimator = estimator, o.threads = 2, o.quiet = true;
    const FirstShotTable t = preprocessScene(s, o);  // a 2 mm patch at 1 m is 0.26 px wide; the plane 128 px
    double sum = 0, sq = 0;
    size_t zero = 0;
    for (uint32_t j = 0; j < t.mesh.size(); ++j) {
      const Patch& p = t.mesh.patches[j];
      const std::vector<Vec3d> poly = {Vec3d(p.v[0]), Vec3d(p.v[1]), Vec3d(p.v[2]), Vec3d(p.v[3])};
      const double exact = analytic::solidAnglePolygon(Vec3d(0, 1, 0), poly) / (4 * kPi);
      const double got = rowSum(t, j) * p.area;
      sum += got, sq += (got - exact) * (got - exact) / (exact * exact);
      zero += got == 0;
    }
    const std::vector<Vec3d> plane = {{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}};
    const double exactSum = analytic::solidAnglePolygon(Vec3d(0, 1, 0), plane) / (4 * kPi);
    const double rms = std::sqrt(sq / t.mesh.size());
    std::printf("%s: %u patches of 0.26 px: %zu get nothing, per-patch RMS rel. error %.2e, total rel. error %.2e\n",
                estimator, t.mesh.size(), zero, rms, std::abs(sum - exactSum) / exactSum);
    EXPECT_NEAR(sum, exactSum, 0.01 * exactSum) << estimator;  // the total is right
    if (std::string(estimator) == "pixels") {
      EXPECT_GT(zero, t.mesh.size() / 2);  // ...but most get nothing
    } else {
      EXPECT_EQ(zero, 0u);  // each its own share
      EXPECT_LT(rms, 1e-5);
      EXPECT_NEAR(sum, exactSum, 1e-5 * exactSum);
    }
  }
}

// A directional light straight down on a floor: r_ij = 1 for every patch (E = E⊥).
TEST(Preprocess, DirectionalLightOnFloor) {
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
    "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": 3}], "settings": {"patch_size": 0.25}})");
  const FirstShotTable t = run(s, 512);
  for (uint32_t j = 0; j < t.mesh.size(); ++j) EXPECT_NEAR(t.irradiance(j).x, 3.0, 3.0 * 0.02) << j;
  EXPECT_NEAR(capturedFlux(t), 4.0, 4.0 * 2e-3);  // Σ r_ij A_j = the lit area
}

TEST(Preprocess, NoSmallLightsGivesAValidEmptyTable) {
  const SceneDesc s = sceneFrom(closedBox("", R"(, {"type": "quad", "material": "lamp", "small": false,
      "vertices": [[0.8,1.4,0.3],[1.2,1.4,0.3],[1.2,1.4,0.7],[0.8,1.4,0.7]]})"));
  const FirstShotTable t = run(s, 64);
  EXPECT_TRUE(t.samples.empty());
  EXPECT_TRUE(t.replacedLights.empty());
  EXPECT_EQ(t.nonZeros(), 0u);
  const std::string path = test::tempDir() + "/empty.fsd";
  writeFirstShot(path, t);
  const FirstShotTable r = readFirstShot(path, hashScene(s));
  EXPECT_EQ(r.mesh.size(), t.mesh.size());
  EXPECT_EQ(r.nonZeros(), 0u);
}

TEST(Preprocess, SameTableForOneAndTwoThreads) {
  const SceneDesc s = loadScene(test::source("scenes/cornell.json"));
  const FirstShotTable a = run(s, 64, "gl", 0.05, 1), b = run(s, 64, "gl", 0.05, 2);
  EXPECT_EQ(a.rowStart, b.rowStart);
  EXPECT_EQ(a.sampleIndex, b.sampleIndex);
  EXPECT_EQ(a.factor, b.factor);
}

// The two back ends agree per patch up to the pixels whose IDs tie on shared edges.
TEST(Preprocess, GLAndEmbreeAgreeOnCornell) {
  const SceneDesc s = loadScene(test::source("scenes/cornell.json"));
  const FirstShotTable g = run(s, 128, "gl", 0.05), e = run(s, 128, "embree", 0.05);
  ASSERT_EQ(g.mesh.size(), e.mesh.size());
  double maxRel = 0, sumG = 0, sumE = 0;
  for (uint32_t j = 0; j < g.mesh.size(); ++j) {
    const double a = g.irradiance(j).x, b = e.irradiance(j).x;
    sumG += a * g.mesh.patches[j].area, sumE += b * e.mesh.patches[j].area;
    if (a > 0.05 * 17) maxRel = std::max(maxRel, std::abs(a - b) / a);  // well-lit patches
  }
  std::printf("GL vs Embree: total flux %.6f vs %.6f, max per-patch rel. difference %.4f\n", sumG, sumE, maxRel);
  EXPECT_NEAR(sumG, sumE, 1e-3 * sumG);
  EXPECT_LT(maxRel, 0.03);
}

TEST(Preprocess, RotatedWindowsKeepFlux) {
  const SceneDesc s = sceneFrom(closedBox(R"({"type": "point", "position": [0.7, 0.9, 0.4], "power": 5})"));
  PreprocessOptions o = defaultOptions(s);
  o.settings.resolution = 128, o.settings.rotationSeed = 7, o.quiet = true;
  const FirstShotTable t = preprocessScene(s, o);
  EXPECT_NEAR(capturedFlux(t), 1.0, 1e-3);
}

// The analytic estimator under partial occlusion: an occluder edge casts a straight shadow across a
// row of patches; the visible part of each is known in closed form. The analytic estimator keeps
// only the aliasing along the shadow edge, so it must be at least as accurate as the pixel sums.
TEST(Preprocess, AnalyticEstimatorUnderPartialOcclusion) {
  // Light at (0,1,0); occluder at height 0.5 covering x < 0.03 casts a shadow edge at x = 0.06 on the floor.
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "quad", "material": "m", "vertices": [[-2,0.5,-2],[-2,0.5,2],[0.03,0.5,2],[0.03,0.5,-2]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}], "settings": {"patch_size": 0.1}})");
  const Vec3d eye(0, 1, 0);
  double sq[2] = {0, 0}, mx[2] = {0, 0};
  int n = 0;
  const char* names[2] = {"pixels", "analytic"};
  FirstShotTable t[2];
  for (int e = 0; e < 2; ++e) {
    PreprocessOptions o = defaultOptions(s);
    o.settings.resolution = 512, o.settings.estimator = names[e], o.quiet = true;
    o.settings.minPatchSize = o.settings.patchSize;  // uniform: the test knows each patch's exact share
    t[e] = preprocessScene(s, o);
  }
  for (uint32_t j = 0; j < t[0].mesh.size(); ++j) {
    const Patch& p = t[0].mesh.patches[j];
    if (p.normal.y < 0.5f || p.centroid.y > 0.01f) continue;  // floor patches only
    const float x0 = std::min({p.v[0].x, p.v[1].x, p.v[2].x, p.v[3].x}), x1 = std::max({p.v[0].x, p.v[1].x, p.v[2].x, p.v[3].x});
    const float z0 = std::min({p.v[0].z, p.v[1].z, p.v[2].z, p.v[3].z}), z1 = std::max({p.v[0].z, p.v[1].z, p.v[2].z, p.v[3].z});
    const double lit0 = std::max<double>(x0, 0.06);
    const double exact = lit0 >= x1 ? 0.0
                                    : analytic::solidAnglePolygon(eye, {{lit0, 0, z0}, {lit0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}}) /
                                          (4 * kPi * p.area);
    if (!(x0 < 0.06 && x1 > 0.06)) {  // wholly lit or wholly shadowed: the analytic estimator is exact
      EXPECT_NEAR(rowSum(t[1], j), exact, 1e-5 * std::max(exact, 1.0)) << j;
      continue;
    }
    ++n;
    for (int e = 0; e < 2; ++e) {
      const double rel = std::abs(rowSum(t[e], j) - exact) / exact;
      sq[e] += rel * rel, mx[e] = std::max(mx[e], rel);
    }
  }
  ASSERT_EQ(n, 20);  // one column of 20 patches straddles the shadow edge
  for (int e = 0; e < 2; ++e)
    std::printf("half-shadowed patches, %s: max rel. error %.4f, RMS %.4f\n", names[e], mx[e], std::sqrt(sq[e] / n));
  EXPECT_LE(std::sqrt(sq[1] / n), std::sqrt(sq[0] / n));
  EXPECT_LT(mx[1], 0.1);  // at most one pixel column of the ~10 lit ones
}
