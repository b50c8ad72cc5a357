// An emissive sphere's light samples (preprocess/sphere_light.h): one at the centre of a sphere far
// from its receivers, twelve on a shell of one near them, its surface's samples where a receiver
// touches it; their irradiance against the sphere's triangles' exact one, the shell's error bound,
// and the quadrature they are checked against.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/scene/scene_shapes.h"
#include "preprocess/light_samples.h"
#include "preprocess/sphere_light.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

/// A 4 × 3 × 4 m room seen from inside with an emissive sphere (radiance 100) of radius @p r at @p centre.
SceneDesc roomWithSphere(const Vec3d& centre, double r, int subdivisions = 4) {
  return test::sceneFromJson(fmt::format(
      R"({{"materials": {{"white": {{"type": "diffuse", "albedo": 0.5}}, "lamp": {{"type": "diffuse", "emission": 100}}}},
    "shapes": [{{"type": "box", "material": "white", "min": [0,0,0], "max": [4,3,4], "flip_normals": true}},
               {{"type": "sphere", "material": "lamp", "center": [{}, {}, {}], "radius": {}, "subdivisions": {}}}]}})",
      centre.x, centre.y, centre.z, r, subdivisions));
}

uint32_t sphereLight(const SceneDesc& d) {
  for (uint32_t i = 0; i < d.lights.size(); ++i)
    if (d.lights[i].type == LightType::Area) return i;
  return 0;
}

double sphereArea(const SceneDesc& d) {
  const ShapeDesc& s = d.shapes[d.lights[sphereLight(d)].shape];
  double a = 0;
  for (const Face& f : s.faces) a += shapes::faceArea(s, f);
  return a;
}

/// The unoccluded irradiance isotropic samples (emission: power, W) give point @p x of normal @p n, channel 0.
double samplesIrradiance(const std::vector<LightSample>& samples, const Vec3d& x, const Vec3d& n) {
  double e = 0;
  for (const LightSample& s : samples) {
    const Vec3d d = Vec3d(s.position) - x;
    const double l = glm::length(d);
    e += double(s.emission.x) / (4 * kPi) * std::max(0.0, glm::dot(d, n) / l) / (l * l);
  }
  return e;
}

/// The exact irradiance of the sphere's triangles at @p x (normal @p n), channel 0.
double trianglesIrradiance(const SceneDesc& d, const Vec3d& x, const Vec3d& n) {
  const ShapeDesc& s = d.shapes[d.lights[sphereLight(d)].shape];
  double e = 0;
  for (const Face& t : s.faces) {
    const Vec3d tri[3] = {s.vertices[t.v[0]], s.vertices[t.v[1]], s.vertices[t.v[2]]};
    if (glm::dot(x - tri[0], glm::cross(tri[1] - tri[0], tri[2] - tri[0])) > 0) e += analytic::polygonCosineSolidAngle(x, n, tri, 3);
  }
  return e * d.materials[s.material].emission.x;
}

// A 2 cm sphere 1.2 m under the ceiling: C·(h/d)² = 0.0003 ≤ 0.01, one sample at the centre with the
// triangles' power π·Le·A, and every room face's irradiance as the triangles give it.
TEST(SphereLight, AFarSphereIsOneSampleAtItsCentre) {
  const SceneDesc d = roomWithSphere(Vec3d(2, 1.8, 2), 0.01);
  const std::vector<LightSample> s = makeLightSamples(d, {sphereLight(d)}, 0.0, d.settings.lightTolerance);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].kind, LightSampleKind::Point);
  EXPECT_NEAR(glm::length(Vec3d(s[0].position) - Vec3d(2, 1.8, 2)), 0.0, 1e-6);
  EXPECT_NEAR(s[0].emission.x, 100 * kPi * sphereArea(d), 1e-4 * s[0].emission.x);
  for (const auto& [x, n] : {std::pair{Vec3d(2, 3, 2), Vec3d(0, -1, 0)}, std::pair{Vec3d(0.5, 0, 3), Vec3d(0, 1, 0)},
                             std::pair{Vec3d(0, 2, 1), Vec3d(1, 0, 0)}})
    EXPECT_NEAR(samplesIrradiance(s, x, n) / trianglesIrradiance(d, x, n), 1.0, 2e-3);
}

// The shipped bulb room's 5 cm bulb 0.55 m under the ceiling: twelve samples on a shell within the
// sphere, the triangles' power in all, and on each room face (a 5 × 5 grid of points) the irradiance
// of the triangles within light_tolerance (was ~150 surface samples).
TEST(SphereLight, ANearSphereIsTwelveSamplesOnAShellThatLightTheRoomAsItsTriangles) {
  const SceneDesc d = loadScene(test::source("scenes/bulb-room.json"));
  const uint32_t light = sphereLight(d);
  const std::vector<LightSample> s = makeLightSamples(d, {light}, 0.0, d.settings.lightTolerance);
  ASSERT_EQ(s.size(), 12u);
  const std::optional<SphereLightFit> fit = fitSphereLight(d, light, d.settings.lightTolerance);
  ASSERT_TRUE(fit);
  double power = 0;
  for (const LightSample& x : s) {
    EXPECT_EQ(x.kind, LightSampleKind::Point);
    EXPECT_NEAR(glm::length(Vec3d(x.position) - fit->centre), fit->shell, 1e-5);
    power += x.emission.x;
  }
  EXPECT_LE(fit->shell, fit->radius * std::sqrt(3.0) / 2 + 1e-9);
  EXPECT_NEAR(power, d.materials[d.shapes[d.lights[light].shape].material].emission.x * kPi * sphereArea(d), 1e-4 * power);
  const ShapeDesc& room = d.shapes[0];
  for (const Face& f : room.faces) {
    const Vec3d v0 = room.vertices[f.v[0]], e1 = room.vertices[f.v[1]] - v0, e2 = room.vertices[f.v[f.count - 1]] - v0;
    const Vec3d n = glm::normalize(glm::cross(e1, e2));
    double worst = 0;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j) {
        const Vec3d x = v0 + (i + 0.5) / 5 * e1 + (j + 0.5) / 5 * e2;
        worst = std::max(worst, std::abs(samplesIrradiance(s, x, n) / trianglesIrradiance(d, x, n) - 1));
      }
    fmt::print("face facing ({:+.0f} {:+.0f} {:+.0f}): worst point {:.4f}%\n", n.x, n.y, n.z, 100 * worst);
    EXPECT_LT(worst, d.settings.lightTolerance);
  }
}

// The shell's error bound: twelve samples on a shell of radius ρ = r·√3/2 against the sphere's exact
// irradiance (Lambert: Le·π·r²·cosθ/D², the receiver's plane clear of the sphere) at receivers at
// distances D from 1.5 r to 4 r, random normals that see the whole sphere: within K·(ρ/D)⁶.
TEST(SphereLight, TwelveSamplesOnAShellMeetTheirErrorBound) {
  const double r = 0.1;
  const SceneDesc d = roomWithSphere(Vec3d(2, 1.5, 2), r, 5);  // receivers ≥ 1.4 m away: the shell's largest radius
  const std::vector<LightSample> s = makeLightSamples(d, {sphereLight(d)}, 0.0, 1e-5);  // 12, not 1
  ASSERT_EQ(s.size(), 12u);
  const double shell = glm::length(Vec3d(s[0].position) - Vec3d(2, 1.5, 2)), le = 100, area = sphereArea(d);
  EXPECT_NEAR(shell, r * std::sqrt(3.0) / 2, 1e-3 * r);
  Sampler rng(7, 0, 0);
  double worstRatio = 0;
  for (int k = 0; k < 2000; ++k) {
    const double D = r * (1.5 + 2.5 * rng.next1D());
    Vec3d u = glm::normalize(Vec3d(rng.next1D() - 0.5, rng.next1D() - 0.5, rng.next1D() - 0.5));
    const Vec3d x = Vec3d(2, 1.5, 2) + D * u;
    Vec3d n = glm::normalize(-u + 0.9 * Vec3d(rng.next1D() - 0.5, rng.next1D() - 0.5, rng.next1D() - 0.5));
    const double offset = glm::dot(n, Vec3d(2, 1.5, 2) - x);
    if (offset <= r) continue;  // the sphere partly under the horizon
    const double exact = le * area / 4 * offset / (D * D * D);  // I·cosθ/D², I = Le·A/4
    worstRatio = std::max(worstRatio, std::abs(samplesIrradiance(s, x, n) / exact - 1) / std::pow(shell / D, 6));
  }
  fmt::print("worst |error| / (ρ/D)⁶: {:.2f} (K = {})\n", worstRatio, kShellErrorConstant);
  EXPECT_GT(worstRatio, 0.5);  // the bound is the error's order, not a loose guess
  EXPECT_LT(worstRatio, kShellErrorConstant);
}

// What the cut faces are checked against: the quadrature of the sphere's surface against Lambert's
// closed form where the whole sphere is above the horizon, and against the triangles' exact irradiance
// where the receiver's plane passes through the sphere (a floor point beside a sphere sunk halfway).
TEST(SphereLight, TheQuadratureOfTheSphereMatchesItsClosedForms) {
  const SceneDesc d = roomWithSphere(Vec3d(2, 1.5, 2), 0.3, 6);
  const std::optional<SphereLightFit> fit = fitSphereLight(d, sphereLight(d), 0.01);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->radius, 0.3, 1e-6);
  EXPECT_NEAR(fit->distance, 1.2, 1e-6);
  EXPECT_NEAR(sphereIrradiance(*fit, Vec3d(2, 3, 2), Vec3d(0, -1, 0)), kPi * 0.09 / (1.5 * 1.5), 2e-3 * kPi * 0.09 / 2.25);
  for (const auto& [x, n] : {std::pair{Vec3d(2.4, 1.5, 2), Vec3d(0, 1, 0)}, std::pair{Vec3d(2.5, 1.4, 2.2), Vec3d(0, 1, 0)}}) {
    const double exact = trianglesIrradiance(d, x, n) / 100;
    EXPECT_NEAR(sphereIrradiance(*fit, x, n) / exact, 1.0, 0.01) << x.x << " " << x.y;
  }
}

// A sphere lamp sunk into the floor (a receiver cuts it: points beside it see part of it under their
// horizon) is sampled on its surface as a mesh; so is one whose light patch size is given (the user's
// tessellation).
TEST(SphereLight, ASphereCutByAReceiverIsSampledOnItsSurface) {
  const SceneDesc d = roomWithSphere(Vec3d(2, 0.1, 2), 0.2);
  const std::vector<LightSample> s = makeLightSamples(d, {sphereLight(d)}, 0.0, d.settings.lightTolerance);
  ASSERT_GT(s.size(), 12u);
  for (const LightSample& x : s) EXPECT_EQ(x.kind, LightSampleKind::AreaVertex);
  const SceneDesc far = roomWithSphere(Vec3d(2, 1.8, 2), 0.01);
  for (const LightSample& x : makeLightSamples(far, {sphereLight(far)}, 0.005, far.settings.lightTolerance))
    EXPECT_EQ(x.kind, LightSampleKind::AreaVertex);
}

}  // namespace
}  // namespace firstshot
