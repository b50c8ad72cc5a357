// The primary method of the irradiance cache (one record, no interpolation) against analytic
// values for a point on a plane lit by a large uniform emitter, which the cache gathers (Ward
// 1988, §5): the irradiance E = π·L·F (point-to-polygon form factor), the harmonic mean
// distance R, and Ward & Heckbert's rotational and translational gradients against finite
// differences of the analytic E. Also: a small emitter's light is not gathered (it is direct
// light); the per-level accuracy and sample counts of §3.4.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>

#include "common/lights/form_factors.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/render_util.h"
#include "tests/stats.h"

using namespace firstshot;

namespace {

constexpr double kLe = 2.0;  // emitted radiance

/// A large floor y = 0 and one emissive quad (counter-clockwise seen from the front).
std::string sceneWith(const std::vector<Vec3d>& quad, bool small) {
  std::string v;
  for (const Vec3d& p : quad) v += fmt::format("{}[{},{},{}]", v.empty() ? "" : ",", p.x, p.y, p.z);
  return fmt::format(R"({{
    "camera": {{"position": [0, 3, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_y": 40, "resolution": [16, 16]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": 0.5}}, "panel": {{"type": "diffuse", "albedo": 0, "emission": {}}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-20,0,-20],[-20,0,20],[20,0,20],[20,0,-20]]}},
               {{"type": "quad", "material": "panel", "vertices": [{}], "small": {}}}],
    "settings": {{"patch_size": 5}}}})", kLe, v, small ? "true" : "false");
}

/// A hit on the floor at @p p (normal +y), as the tracer would report it.
Hit floorHit(const Vec3& p) {
  Hit h;
  h.p = p;
  h.ng = Vec3(0, 1, 0);
  h.patch = 0;
  h.t = 1.0f;
  return h;
}

double analyticE(const std::vector<Vec3d>& quad, const Vec3d& x, const Vec3d& n) {
  return kPi * kLe * analytic::pointPolygonFormFactor(x, n, quad);
}

struct Gathered {
  test::RunningStats E, invR, gradT[3], gradR[3];  // red channel; gradients per world axis
};

/// @p count records at @p p, each from its own seed.
Gathered gatherRecords(const IrradianceCacheIntegrator& ic, const Vec3& p, int count) {
  Gathered g;
  for (int i = 0; i < count; ++i) {
    Sampler s(11, uint64_t(i), 0);
    const IrradianceRecord r = ic.computeRecord(floorHit(p), Vec3(0, 1, 0), 0, s);
    g.E.add(r.E.x);
    g.invR.add(1.0 / r.R);
    for (int k = 0; k < 3; ++k) g.gradT[k].add(r.gradT[0][k]), g.gradR[k].add(r.gradR[0][k]);
  }
  return g;
}

IrradianceCacheSettings gatherSettings(int samples) {
  IrradianceCacheSettings s;
  s.samples = samples;
  s.bounces = 1;
  s.footprintMin = 0.0f;
  s.footprintMax = std::numeric_limits<float>::infinity();
  return s;
}

}  // namespace

TEST(IrradianceGather, IrradianceAndHarmonicMeanDistanceUnderALargeCeiling) {
  // A 4 m × 4 m panel 1 m above the point, facing down.
  const double h = 1.0, w = 2.0;
  const std::vector<Vec3d> quad = {{-w, h, -w}, {w, h, -w}, {w, h, w}, {-w, h, w}};
  const SceneDesc desc = test::sceneFromJson(sceneWith(quad, false));
  const RenderScene scene(desc);
  IrradianceCacheIntegrator ic(IntegratorOptions{}, gatherSettings(512));
  ic.preprocess(scene);
  ASSERT_TRUE(ic.gatheredLights()[0]) << "the panel is large: its light is gathered";

  const Vec3 x(0.3f, 0.0f, -0.2f);
  const Gathered g = gatherRecords(ic, x, 48);
  const double E = analyticE(quad, Vec3d(x), Vec3d(0, 1, 0));
  // E[1/R] = E_cos[1/r] = (1/π)∫_panel cos²θ/h dω: midpoint quadrature over the panel
  // (dω = cosθ_L dA / r², cosθ = cosθ_L = h/r).
  double integral = 0;
  const int q = 800;
  const double dA = (2 * w / q) * (2 * w / q);
  for (int i = 0; i < q; ++i)
    for (int j = 0; j < q; ++j) {
      const Vec3d y(-w + (i + 0.5) * 2 * w / q, h, -w + (j + 0.5) * 2 * w / q);
      const double r = glm::length(y - Vec3d(x));
      integral += std::pow(h / r, 3) / (r * r) * dA / h;
    }
  const double invR = integral / kPi;
  fmt::print("E = {:.5f} ± {:.5f} (analytic {:.5f}); 1/R = {:.5f} ± {:.5f} (expected {:.5f}, R = {:.4f} m)\n", g.E.mean,
             g.E.standardError(), E, g.invR.mean, g.invR.standardError(), invR, 1 / invR);
  EXPECT_GT(g.E.standardError(), 0.0);
  EXPECT_NEAR(g.E.mean, E, 4 * g.E.standardError() + 1e-4 * E);
  EXPECT_NEAR(g.invR.mean, invR, 4 * g.invR.standardError() + 1e-3 * invR);
}

TEST(IrradianceGather, SmallLightsAreNotGathered) {
  // The same panel marked small: its light is direct light (NEE or first-shot), so the gathered
  // irradiance is exactly zero, while its distance still enters R.
  const std::vector<Vec3d> quad = {{-2, 1, -2}, {2, 1, -2}, {2, 1, 2}, {-2, 1, 2}};
  const SceneDesc desc = test::sceneFromJson(sceneWith(quad, true));
  const RenderScene scene(desc);
  IrradianceCacheIntegrator ic(IntegratorOptions{}, gatherSettings(128));
  ic.preprocess(scene);
  EXPECT_FALSE(ic.gatheredLights()[0]);
  Sampler s(1, 2, 3);
  const IrradianceRecord r = ic.computeRecord(floorHit(Vec3(0)), Vec3(0, 1, 0), 0, s);
  EXPECT_EQ(r.E, Color(0.0f));
  EXPECT_LT(r.R, 2.0f);
  EXPECT_GT(r.R, 1.0f);
}

TEST(IrradianceGather, GradientsMatchFiniteDifferencesOfTheAnalyticIrradiance) {
  // A vertical panel 0.5 m beside the point (x = 0.5, 1 m high, 2 m wide, facing −x): E changes
  // fast along x and with the normal's tilt towards the panel.
  const std::vector<Vec3d> quad = {{0.5, 0, -1}, {0.5, 0, 1}, {0.5, 1, 1}, {0.5, 1, -1}};
  const SceneDesc desc = test::sceneFromJson(sceneWith(quad, false));
  const RenderScene scene(desc);
  IrradianceCacheIntegrator ic(IntegratorOptions{}, gatherSettings(1024));
  ic.preprocess(scene);
  const Vec3d x(0.0, 0.0, 0.3), up(0, 1, 0);
  const Gathered g = gatherRecords(ic, Vec3(x), 24);

  const double eps = 1e-4;
  auto E = [&](const Vec3d& p, const Vec3d& n) { return analyticE(quad, p, n); };
  // Translational: ∂E/∂x and ∂E/∂z on the floor.
  const double dEdx = (E(x + Vec3d(eps, 0, 0), up) - E(x - Vec3d(eps, 0, 0), up)) / (2 * eps);
  const double dEdz = (E(x + Vec3d(0, 0, eps), up) - E(x - Vec3d(0, 0, eps), up)) / (2 * eps);
  // Rotational: rotating N about axis a by α changes E by α·(∇r·a).
  auto tilt = [&](const Vec3d& axis, double a) { return std::cos(a) * up + std::sin(a) * glm::cross(axis, up); };
  const double dEdRotZ = (E(x, tilt(Vec3d(0, 0, 1), eps)) - E(x, tilt(Vec3d(0, 0, 1), -eps))) / (2 * eps);
  const double dEdRotX = (E(x, tilt(Vec3d(1, 0, 0), eps)) - E(x, tilt(Vec3d(1, 0, 0), -eps))) / (2 * eps);
  fmt::print("E {:.4f} ± {:.4f} (analytic {:.4f})\n", g.E.mean, g.E.standardError(), E(x, up));
  fmt::print("translational: x {:+.4f} ± {:.4f} (finite differences {:+.4f}), z {:+.4f} ± {:.4f} ({:+.4f}), y {:+.2e}\n",
             g.gradT[0].mean, g.gradT[0].standardError(), dEdx, g.gradT[2].mean, g.gradT[2].standardError(), dEdz,
             g.gradT[1].mean);
  fmt::print("rotational: about z {:+.4f} ± {:.4f} ({:+.4f}), about x {:+.4f} ± {:.4f} ({:+.4f})\n", g.gradR[2].mean,
             g.gradR[2].standardError(), dEdRotZ, g.gradR[0].mean, g.gradR[0].standardError(), dEdRotX);
  // The translational gradient is Ward & Heckbert's estimate from the cell boundaries (edges of
  // the panel fall inside cells, distances vary within them): allow 10 % of the larger derivative
  // beside 4 standard errors. The rotational one is an integral, exact for L constant per cell: 2 %.
  const double tolT = 0.1 * std::max(std::abs(dEdx), std::abs(dEdz)), tolR = 0.02 * std::max(std::abs(dEdRotZ), std::abs(dEdRotX));
  EXPECT_NEAR(g.gradT[0].mean, dEdx, 4 * g.gradT[0].standardError() + tolT);
  EXPECT_NEAR(g.gradT[2].mean, dEdz, 4 * g.gradT[2].standardError() + tolT);
  EXPECT_NEAR(g.gradT[1].mean, 0.0, 1e-4);  // in the tangent plane
  EXPECT_NEAR(g.gradR[2].mean, dEdRotZ, 4 * g.gradR[2].standardError() + tolR);
  EXPECT_NEAR(g.gradR[0].mean, dEdRotX, 4 * g.gradR[0].standardError() + tolR);
  EXPECT_NEAR(g.gradR[1].mean, 0.0, 1e-4);
  // Sanity: the configuration has sizeable gradients.
  EXPECT_GT(std::abs(dEdx), 0.5 * E(x, up));
  EXPECT_GT(std::abs(dEdRotZ), 0.2 * E(x, up));
}

TEST(IrradianceGather, DeeperLevelsUseLargerAccuracyAndHalfTheSamples) {
  IrradianceCacheSettings s;
  s.accuracy = 0.2f;
  s.samples = 512;
  const IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  for (int l = 0; l < 4; ++l) {
    EXPECT_NEAR(ic.accuracy(l), 0.2 * std::pow(1.4, l), 1e-6);
    const int M = ic.strata(l);
    const double n = 2.0 * M * M, expected = 512.0 / std::pow(2.0, l);
    fmt::print("level {}: a = {:.3f}, {} × {} = {} samples\n", l, ic.accuracy(l), M, 2 * M, int(n));
    EXPECT_NEAR(n / expected, 1.0, 0.25) << "level " << l;
  }
  EXPECT_EQ(ic.strata(0), 16);  // Ward's 2n² with n = 16
}
