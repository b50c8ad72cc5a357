// The adjoint identity as the oracle (Dutré et al.; docs/light-tracing.md): shooting (light
// subpaths) and gathering (path tracing) estimate the same fluxes, and the first-shot table's
// direct irradiance is what the particles deposit at their first hit.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/sampling/sampling.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/path/integrator.h"
#include "tests/bias_util.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

/// The flux onto the Cornell floor S (W, channel mean) carried by light that has bounced at most
/// depth − 1 times before reaching S. (The floor is one white material.)
struct FloorFlux {
  test::Moments shooting, gathering;
};

FloorFlux cornellFloorFlux(int depth, uint64_t particles, int points) {
  const SceneDesc d = loadScene(test::source("scenes/cornell.json"));
  const RenderScene scene(d, d.settings.patchSize);
  std::vector<uint32_t> floor;
  double area = 0;
  for (uint32_t j = 0; j < scene.mesh().size(); ++j)
    if (d.shapes[scene.mesh().patches[j].shape].name.find("floor") != std::string::npos)
      floor.push_back(j), area += scene.mesh().patches[j].area;
  EXPECT_GT(floor.size(), 10u);
  FloorFlux r;

  // Shooting: every hit of a particle on S deposits the power it carries (vertex k ≥ 1 arrives after k − 1 bounces).
  IntegratorOptions io;
  io.maxDepth = depth;
  LightTracingIntegrator lt(io);
  lt.preprocess(scene);
  std::vector<double> x(particles, 0.0);
  test::forEachLightPath(scene, lt, particles, 3, [&](uint64_t i, const std::vector<LightVertex>& path) {
    for (size_t k = 1; k < path.size(); ++k)
      if (std::find(floor.begin(), floor.end(), path[k].hit.patch) != floor.end()) x[i] += test::gray(path[k].beta);
  });
  for (double v : x) r.shooting.add(v);

  // Gathering: a uniform point x of S and the path tracer's radiance reflected there, seen from just
  // above x: at x it samples the lights (NEE) and the cosine-weighted Lambertian lobe, with MIS, so
  // L_o = ρ/π·E(x) with light of at most depth − 1 bounces before S; flux = A_S·E = A_S·π·L_o/ρ.
  io.maxDepth = depth;
  PathIntegrator pt(io);
  pt.preprocess(scene);
  std::vector<double> cdf;
  for (uint32_t j : floor) cdf.push_back((cdf.empty() ? 0.0 : cdf.back()) + scene.mesh().patches[j].area / area);
  const Color rho = scene.bsdf(scene.mesh().patches[floor[0]].material).albedo();
  std::vector<double> y(size_t(points), 0.0);
  tbb::parallel_for(0, points, [&](int i) {
    Sampler s(5, uint64_t(i), 0);
    const double u = s.next1Dd();
    const size_t k = std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()), cdf.size() - 1);
    const Patch& p = scene.mesh().patches[floor[k]];
    const Vec3 n = p.normal.y > 0 ? p.normal : -p.normal;  // into the room
    const Vec3 q = test::samplePatch(p, s.next2D());
    uint64_t rays = 0;
    const Color L = pt.walk().trace(Ray(q + 1e-3f * n, -n), Color(1.0f), 0, PathVertex(), true, s, rays);
    y[size_t(i)] = area * kPi * test::gray(L / rho);
  });
  for (double v : y) r.gathering.add(v);
  return r;
}

/// A first-shot table at the scene's settings on a uniform mesh (Embree item buffers, R = 256).
FirstShotTable table(const SceneDesc& s) {
  PreprocessOptions o = defaultOptions(s);
  o.settings.backend = "embree";
  o.settings.minPatchSize = o.settings.patchSize;  // uniform
  o.quiet = true;
  return preprocessScene(s, o);
}

/// Approximate item-buffer pixels of patch @p p seen from @p eye at resolution @p R: its solid
/// angle over the pixel's 4/R² at a face centre (pixels off-centre are smaller: a lower bound).
double itemBufferPixels(const Patch& p, const Vec3& eye, int R) {
  std::vector<Vec3d> poly;
  for (uint32_t k = 0; k < p.count; ++k) poly.emplace_back(p.v[k]);
  return analytic::solidAnglePolygon(Vec3d(eye), poly) * R * R / 4.0;
}

/// Per patch, the table's direct irradiance against the light tracer's first-hit irradiance.
void expectTableMatchesShooting(const std::string& what, const std::string& json, const Vec3* eye) {
  const SceneDesc d = test::sceneFromJson(json);
  const RenderScene scene(d, table(d));
  const FirstShotTable& t = *scene.firstShot();
  ASSERT_FALSE(t.replacedLights.empty()) << what;
  IntegratorOptions io;
  io.maxDepth = 1;
  io.shootFromPatches = false;  // shoot the small lights themselves
  LightTracingIntegrator lt(io);
  lt.preprocess(scene);
  const uint64_t n = 400000;
  std::vector<uint32_t> patch(n, kNoId);
  std::vector<double> power(n, 0.0);
  test::forEachLightPath(scene, lt, n, 9, [&](uint64_t i, const std::vector<LightVertex>& path) {
    if (path.size() > 1 && path[1].hit.onPatch()) patch[i] = path[1].hit.patch, power[i] = test::gray(path[1].beta);
  });
  const uint32_t m = t.mesh.size();
  std::vector<double> sum(m, 0.0), sum2(m, 0.0);
  for (uint64_t i = 0; i < n; ++i)
    if (patch[i] != kNoId) sum[patch[i]] += power[i], sum2[patch[i]] += power[i] * power[i];
  int tested = 0, beyond3 = 0;
  double worst = 0, chi2 = 0;
  for (uint32_t j = 0; j < m; ++j) {
    const Patch& p = t.mesh.patches[j];
    if (eye && itemBufferPixels(p, *eye, int(t.settings.resolution)) < 10) continue;
    const double mean = sum[j] / double(n), se = std::sqrt(std::max(0.0, sum2[j] / double(n) - mean * mean) / double(n - 1));
    // A patch no particle reached has no sample variance: its resolution is one particle's deposit.
    const double shot = mean / p.area, tab = test::gray(t.irradiance(j));
    const double shotSe = sum[j] > 0 ? se / p.area : lt.emission().totalPower() / double(n) / p.area;
    if (shot == 0 && tab == 0) continue;
    ++tested;
    const double z = std::abs(shot - tab) / shotSe;
    worst = std::max(worst, z);
    chi2 += z * z;
    beyond3 += z > 3;
    EXPECT_LT(std::abs(shot - tab), 4 * shotSe) << what << " patch " << j << ": table " << tab << " W/m², shooting " << shot
                                                << " ± " << shotSe;
  }
  fmt::print("{}: {} patches, {} beyond 3σ, worst {:.2f}σ, mean z² {:.3f}\n", what, tested, beyond3, worst, chi2 / tested);
  EXPECT_GT(tested, 20) << what;
  // With ~100–200 patches a few tenths of a patch lie beyond 3σ by chance: allow 1% (at least one),
  // none beyond 4σ (above), and no systematic excess: the mean of z² is 1 ± √(2/n) for unbiased tables.
  EXPECT_LE(beyond3, std::max(1, tested / 100)) << what;
  EXPECT_LT(chi2 / tested, 1.0 + 4.0 * std::sqrt(2.0 / tested)) << what;
}

std::string room(const std::string& lights, const std::string& shapes = "", const std::string& settings = "") {
  return R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": [4, 3, 2]}},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [2,1.5,1], "flip_normals": true},
               {"type": "box", "material": "white", "min": [0.6,0.35,0.25], "max": [1.0,0.55,0.6]})" +
         shapes + R"(], "lights": [)" + lights + R"(], "settings": {"patch_size": 0.25)" + settings + "}}";
}

}  // namespace

// The first-shot table against shooting: per patch of ≥ 10 item-buffer pixels, the table's
// Σ_i Le_i r_ij equals the irradiance of the particles' first hits (a floating box casts shadows).
TEST(LightTracingAdjoint, FirstShotTableMatchesFirstHitsPointLight) {
  const Vec3 eye(1.2f, 1.1f, 0.5f);
  expectTableMatchesShooting("point", room(R"({"type": "point", "position": [1.2, 1.1, 0.5], "power": [3, 2, 1]})"), &eye);
}

TEST(LightTracingAdjoint, FirstShotTableMatchesFirstHitsSpotLight) {
  const Vec3 eye(1.2f, 1.2f, 0.5f);
  expectTableMatchesShooting("spot", room(R"({"type": "spot", "position": [1.2, 1.2, 0.5], "direction": [-0.3, -1, 0.1],
      "power": 3, "inner_angle": 25, "outer_angle": 50})"), &eye);
}

TEST(LightTracingAdjoint, FirstShotTableMatchesFirstHitsAreaLight) {
  const Vec3 eye(1.2f, 1.49f, 0.5f);
  expectTableMatchesShooting("area", room("", R"(, {"type": "quad", "material": "lamp", "small": true,
      "vertices": [[1.05,1.49,0.35],[1.35,1.49,0.35],[1.35,1.49,0.65],[1.05,1.49,0.65]]})", R"(, "light_patch_size": 0.05)"), &eye);
}

TEST(LightTracingAdjoint, FirstShotTableMatchesFirstHitsDirectionalLight) {
  // Open: a floor and a floating box under a slanted sun. Every patch is ≥ 0.2 m wide, ≥ 400
  // pixels of the orthographic item buffer at R = 256.
  expectTableMatchesShooting("directional", R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "box", "material": "white", "min": [-0.3,0.3,-0.3], "max": [0.3,0.6,0.2]}],
    "lights": [{"type": "directional", "direction": [0.4, -1, 0.2], "irradiance": [3, 2, 1]}],
    "settings": {"patch_size": 0.25}})", nullptr);
}

// Flux onto the Cornell floor by shooting and by gathering, for direct light only and for up to 3
// bounces before the floor: equal within 3σ (σ from both estimators' samples).
TEST(LightTracingAdjoint, CornellFloorFluxShootingEqualsGathering) {
  for (int depth : {1, 4}) {
    const FloorFlux f = cornellFloorFlux(depth, 200000, 100000);
    const double a = f.shooting.mean(), b = f.gathering.mean();
    const double se = std::hypot(f.shooting.se(), f.gathering.se());
    fmt::print("depth {}: shooting {:.6f} ± {:.6f} W, gathering {:.6f} ± {:.6f} W, z = {:.2f}\n", depth, a,
               f.shooting.se(), b, f.gathering.se(), (a - b) / se);
    EXPECT_GT(a, 0.0);
    EXPECT_LT(se, 0.01 * b) << "too noisy to test";
    EXPECT_LT(std::abs(a - b), 3.0 * se) << "depth " << depth;
  }
}
