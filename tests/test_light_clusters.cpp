// An emissive mesh's light, both ways the renderer takes it (issue 33, scenes/bulb-room.json: an
// icosphere of 20,480 triangles): the preprocessor's clustered samples must send the triangles'
// radiant intensity on average over directions, and NEE's shadow rays must not stop on the light's
// own grazing triangles. Each bias alone was 0.4–0.5% of the room's image.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/analytic.h"
#include "common/sampling.h"
#include "render/direct_light.h"
#include "render/render_scene.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace fs {
namespace {

/// The shipped bulb room; @p light is set to its emissive sphere's light, @p shape to its shape.
SceneDesc bulbRoom(uint32_t& light, size_t& shape) {
  SceneDesc d = loadScene(test::source("scenes/bulb-room.json"));
  for (uint32_t i = 0; i < d.lights.size(); ++i)
    if (d.lights[i].type == LightType::Area) light = i, shape = size_t(d.lights[i].shape);
  return d;
}

// NEE to the bulb from points around the room: its estimator of the irradiance, shadow rays as the
// renderer casts them, against the triangles' exact irradiance (nothing stands between), within 4σ
// of the samples; and the share of it the shadow rays stopped, which is the estimator's bias here,
// nearly none. Rays shifted parallel to the sampled direction stopped on the sphere's limb, seen at a
// grazing angle: 0.9% of the irradiance on the ceiling beside the bulb, 0.45% on a wall.
TEST(LightShadowRays, NeeToAnEmissiveSphereMatchesTheExactIrradiance) {
  uint32_t light = 0;
  size_t shape = 0;
  const SceneDesc d = bulbRoom(light, shape);
  const RenderScene scene(d, 1.0);
  const ShapeDesc& bulb = d.shapes[shape];
  const RenderLight& l = scene.lights().lights()[light];
  for (const auto& [x, n] : {std::pair{Vec3d(1.01, 3.0, 1.03), Vec3d(0, -1, 0)}, std::pair{Vec3d(3.0, 3.0, 2.5), Vec3d(0, -1, 0)},
                             std::pair{Vec3d(2.0, 1.5, 4.0), Vec3d(0, 0, -1)}, std::pair{Vec3d(0.0, 2.9, 1.0), Vec3d(1, 0, 0)}}) {
    Hit hit;  // as the renderer finds the point: its offset grows with the coordinates and the distance
    ASSERT_TRUE(scene.intersect(Ray(Vec3(x + 2.0 * n), Vec3(-n), 0.0f, 10.0f), hit));
    double exact = 0;
    for (const Face& t : bulb.faces) {
      const Vec3d tri[3] = {bulb.vertices[t.v[0]], bulb.vertices[t.v[1]], bulb.vertices[t.v[2]]};
      if (glm::dot(x - tri[0], glm::cross(tri[1] - tri[0], tri[2] - tri[0])) > 0) exact += analytic::polygonCosineSolidAngle(x, n, tri, 3);
    }
    exact *= l.radiance.x;
    const int count = 1 << 17;
    double sum = 0, sum2 = 0, lost = 0;  // lost: what the shadow rays stopped, which nothing but the light could
    for (int k = 0; k < count; ++k) {
      Sampler sampler(5, uint64_t(k), 0);
      LightRecord rec;
      if (!scene.lights().sample(l, hit.p, sampler.next2D(), rec)) continue;
      const double e = std::max(0.0, glm::dot(Vec3d(rec.wi), n)) * rec.value.x;
      if (scene.occluded(shadowRay(hit, rec.wi, rec.distance))) {
        lost += e;
        continue;
      }
      sum += e, sum2 += e * e;
    }
    const double mean = sum / count, se = std::sqrt(std::max(0.0, sum2 / count - mean * mean) / (count - 1));
    fmt::print("({:.2f} {:.2f} {:.2f}): NEE {:+.3f}% ± {:.3f}% of exact, shadow rays stopped {:.4f}% of it\n", x.x, x.y, x.z,
               100 * (mean / exact - 1), 100 * se / exact, 100 * lost / (sum + lost));
    EXPECT_LT(lost / (sum + lost), 1e-4) << "a convex light cannot shadow its own front";
    EXPECT_LT(std::abs(mean - exact), 4 * se);
  }
}

}  // namespace
}  // namespace fs
