// Table mode of the shooting integrators where one surface lies on another: a mat (a quad of the
// floor's material) coplanar with the floor, right under a small bulb. A ray that arrives there meets
// one of the two coincident patches (the ray tracer's choice), so the gathering estimators, and
// shooting from the bulb itself, count the reflection once; the table lights both patches (each one's
// points see the bulb past the other), and particles that leave a lit patch from a point sampled by
// area used to leave both, counting the mat's area twice (light tracing 9.8% bright on this scene,
// bowl-lamp-room 3.2%: a stand's top under the bowl's bottom). A point sampled on a patch now emits
// only where a ray from its direction meets that patch (patchPointExposed). The materials are the
// same, so the ray tracer's choice does not change the image: table mode must give the image of light
// tracing without a table (image means, σ from the per-pass means).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <string>

#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "preprocess/preprocessor.h"
#include "render/firstshot/patch_emitters.h"
#include "render/loop/renderer.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// A 2 m × 1.5 m × 2 m room (32×24, max depth 6, patches of 0.2 m): a bulb (r = 3 cm, 60 W/(m² sr)) 22 cm above
/// a 40 cm mat that lies on the floor (both at y = 1 mm, albedo 0.6); the camera looks up at the walls and
/// the ceiling, not at the bulb (seen directly, its pixels would carry most of the noise).
SceneDesc matRoom() {
  return test::sceneFromJson(R"({"materials": {"wall": {"type": "diffuse", "albedo": 0.7},
      "floor": {"type": "diffuse", "albedo": 0.6}, "bulb": {"type": "diffuse", "emission": 60}},
    "shapes": [{"type": "box", "material": "wall", "min": [0,0,0], "max": [2,1.5,2], "flip_normals": true},
               {"type": "quad", "material": "floor", "vertices": [[0,0.001,0],[0,0.001,2],[2,0.001,2],[2,0.001,0]]},
               {"type": "quad", "material": "floor", "vertices": [[0.8,0.001,0.8],[0.8,0.001,1.2],[1.2,0.001,1.2],[1.2,0.001,0.8]]},
               {"type": "sphere", "material": "bulb", "center": [1.0, 0.25, 1.0], "radius": 0.03, "subdivisions": 2}],
    "camera": {"position": [1.9, 0.6, 1.9], "look_at": [0.3, 1.4, 0.3], "fov_y": 45, "resolution": [32, 24]},
    "settings": {"patch_size": 0.2, "max_depth": 6}})");
}

/// The scene with its first-shot table (Embree item buffers, R = 64).
RenderScene withTable(const SceneDesc& d) {
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  return RenderScene(d, preprocessScene(d, po));
}

/// The image mean (channel mean) of each of @p passes passes of @p integrator (one sample per pixel each).
test::Moments passMeans(const Integrator& integrator, const RenderScene& scene, int passes, uint64_t seed) {
  const Camera camera(scene.desc().camera);
  test::Moments m;
  for (int k = 0; k < passes; ++k) {
    Film film(camera.width(), camera.height());
    RenderOptions ro;
    ro.spp = 1, ro.firstSample = k, ro.seed = seed;
    render(integrator, camera, film, ro);
    double sum = 0;
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x) {
        const Vec3d c = film.mean(x, y);
        sum += (c.x + c.y + c.z) / 3.0;
      }
    m.add(sum / (double(camera.width()) * camera.height()));
  }
  return m;
}

/// The floor's patch and the mat's patch under the point (x, 1 mm, z): the patches whose planes and
/// outlines hold it.
std::pair<uint32_t, uint32_t> coincidentPatches(const RenderScene& scene, float x, float z) {
  uint32_t found[2] = {kNoId, kNoId};
  int count = 0;
  const PatchMesh& mesh = scene.mesh();
  for (uint32_t j = 0; j < mesh.size() && count < 2; ++j) {
    const Patch& p = mesh.patches[j];
    float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f}, yMax = -1e9f, yMin = 1e9f;
    for (uint32_t k = 0; k < p.count; ++k) {
      lo[0] = std::min(lo[0], p.v[k].x), hi[0] = std::max(hi[0], p.v[k].x);
      lo[1] = std::min(lo[1], p.v[k].z), hi[1] = std::max(hi[1], p.v[k].z);
      yMin = std::min(yMin, p.v[k].y), yMax = std::max(yMax, p.v[k].y);
    }
    if (yMin == 0.001f && yMax == 0.001f && x > lo[0] && x < hi[0] && z > lo[1] && z < hi[1]) found[count++] = j;
  }
  return {found[0], found[1]};
}

class ShootingCoveredPatch : public testing::TestWithParam<std::string> {};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Integrators, ShootingCoveredPatch, testing::Values("light", "bdpt"),
                         [](const testing::TestParamInfo<std::string>& p) { return p.param; });

// The mat's area is counted once: table mode's image mean within 3.5σ of light tracing's without
// the table (before: light +9.8%, 40σ; bdpt +9.5%, 38σ), and σ below 0.5% of the mean.
TEST_P(ShootingCoveredPatch, CoplanarMatAgreesWithoutTheTable) {
  const SceneDesc d = matRoom();
  const RenderScene table = withTable(d), plain(d, d.settings.patchSize);
  ASSERT_FALSE(table.firstShot()->replacedLights.empty());
  IntegratorOptions io;
  io.shootFromPatches = true;
  io.maxDepth = d.settings.maxDepth;
  auto shooter = makeIntegrator(GetParam(), io), reference = makeIntegrator("light", io);
  shooter->preprocess(table);
  reference->preprocess(plain);
  const test::Moments t = passMeans(*shooter, table, 64, 11), r = passMeans(*reference, plain, 64, 12);
  const double se = std::hypot(t.se(), r.se());
  fmt::print("{} with the table {:.5f} ± {:.5f}, light tracing without {:.5f} ± {:.5f} ({:+.2f}σ)\n", GetParam(),
             t.mean(), t.se(), r.mean(), r.se(), (t.mean() - r.mean()) / se);
  EXPECT_LT(t.se(), 0.005 * t.mean()) << "too noisy to test";
  EXPECT_NEAR(t.mean(), r.mean(), 3.5 * se);
}

// The probe itself: at a point of the mat's area, seen from above, exactly one of the two coincident
// patches is the one a ray meets, and so exposed; a floor point beside the mat is exposed.
TEST(ShootingCoveredPatchProbe, OneOfTwoCoincidentPatchesIsExposed) {
  const SceneDesc d = matRoom();
  const RenderScene scene(d, d.settings.patchSize);
  Sampler random(5, 0, 0, 0);
  int single = 0;
  const int n = 200;
  for (int i = 0; i < n; ++i) {
    const float x = 0.81f + 0.38f * random.next1D(), z = 0.81f + 0.38f * random.next1D();
    const auto [a, b] = coincidentPatches(scene, x, z);
    ASSERT_NE(b, kNoId) << x << " " << z;
    const Vec3 y(x, 0.001f, z);
    const Vec3 w = squareToCosineHemisphere(random.next2D());  // about +z: turned to the floor's normal +y
    const Vec3 up = glm::normalize(Vec3(w.x, w.z, w.y));
    single += patchPointExposed(scene, a, y, up) != patchPointExposed(scene, b, y, up) ? 1 : 0;
  }
  EXPECT_EQ(single, n) << "points of the mat where exactly one of the two patches is exposed";
  const auto [floorPatch, none] = coincidentPatches(scene, 0.3f, 0.3f);
  ASSERT_NE(floorPatch, kNoId);
  EXPECT_EQ(none, kNoId);
  EXPECT_TRUE(patchPointExposed(scene, floorPatch, Vec3(0.3f, 0.001f, 0.3f), glm::normalize(Vec3(0.2f, 1.0f, 0.1f))));
}
