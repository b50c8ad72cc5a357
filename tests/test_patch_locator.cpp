// Tracing the faces and finding each hit's patch (render/scene/patch_locator.h): the located patch holds the point,
// and the hits equal those of the patches traced as they are.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "preprocess/preprocessor.h"
#include "render/scene/embree_scene.h"
#include "render/scene/patch_locator.h"
#include "render/scene/render_scene.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

/// A 2 m × 1.5 m × 2 m room lit by a small bulb, with a trapezoid table top (a planar quad that is no
/// parallelogram: inverse bilinear coordinates), an icosahedron's triangles and a box: adaptive patches where their shadows fall.
SceneDesc room() {
  return test::sceneFromJson(R"({"materials": {"wall": {"type": "diffuse", "albedo": 0.7},
      "bulb": {"type": "diffuse", "emission": 60}},
    "shapes": [{"type": "box", "material": "wall", "min": [0,0,0], "max": [2,1.5,2], "flip_normals": true},
               {"type": "quad", "material": "wall", "vertices": [[0.2,0.5,0.2],[0.2,0.5,0.9],[1.1,0.5,0.7],[1.1,0.5,0.4]]},
               {"type": "sphere", "material": "wall", "center": [1.5, 0.4, 1.5], "radius": 0.3, "subdivisions": 0},
               {"type": "box", "material": "wall", "min": [1.2,0,0.2], "max": [1.6,0.4,0.6]},
               {"type": "sphere", "material": "bulb", "center": [1.0, 1.1, 1.0], "radius": 0.03, "subdivisions": 2}],
    "camera": {"position": [1.9, 0.6, 1.9], "look_at": [0.3, 0.6, 0.3], "fov_y": 45, "resolution": [16, 16]},
    "settings": {"patch_size": 0.1, "max_depth": 4}})");
}

FirstShotTable tableOf(const SceneDesc& d) {
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  return preprocessScene(d, po);
}

/// A point inside patch @p p away from its edges: a random point of its triangle fan pulled 10% towards the centroid.
Vec3 insidePoint(const Patch& p, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const uint32_t k = p.count == 4 && u(rng) < 0.5f ? 2 : 1;
  float a = u(rng), b = u(rng);
  if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
  const Vec3 x = p.v[0] + a * (p.v[k] - p.v[0]) + b * (p.v[k + 1] - p.v[0]);
  return p.centroid + 0.9f * (x - p.centroid);
}

}  // namespace

TEST(PatchLocator, FindsThePatchThatHoldsEachPoint) {
  const SceneDesc d = room();
  const FirstShotTable t = tableOf(d);
  const auto locator = PatchLocator::build(d, t.mesh);
  ASSERT_NE(locator, nullptr);
  const uint32_t faces = locator->faces().size();
  EXPECT_EQ(locator->gridFaces(), faces) << "every face's patches are cells of its grid or pieces of one";
  EXPECT_GT(locator->refinedCells(), 10u) << "the refined cells are found as the preprocessor split them";
  std::mt19937 rng(11);
  size_t checked = 0, refined = 0;
  for (uint32_t f = 0; f < faces; ++f)
    for (uint32_t i = 0; i < locator->patchCount(f); ++i) {
      const uint32_t j = locator->patchesOf(f)[i];
      const Patch& p = t.mesh.patches[j];
      refined += p.area < 0.2 * 0.1 * 0.1;  // smaller than a quarter of a grid cell: the adaptive refinement's
      for (int s = 0; s < 4; ++s, ++checked) ASSERT_EQ(locator->locate(f, insidePoint(p, rng)), j) << "face " << f;
    }
  EXPECT_EQ(checked, 4 * size_t(t.mesh.size()));
  for (uint32_t f = 0; f < faces; ++f) {  // a point off the face, or not a point at all: some patch of the face
    const uint32_t* mine = locator->patchesOf(f);
    for (const Vec3& p : {Vec3(NAN), Vec3(1e30f), Vec3(-1e30f, 0.0f, 1e30f)})
      EXPECT_NE(std::find(mine, mine + locator->patchCount(f), locator->locate(f, p)), mine + locator->patchCount(f));
  }
  EXPECT_GT(refined, 100u) << "the test wants refined patches";
}

TEST(PatchLocator, OnlyWherePatchesOutnumberTheFaces) {
  const SceneDesc d = room();
  EXPECT_EQ(PatchLocator::build(d, buildPatches(d, kFacesAsTheyAre)), nullptr);
  const PatchMesh uniform = buildPatches(d, 0.1);
  ASSERT_NE(PatchLocator::build(d, uniform), nullptr);
  PatchMesh moved = uniform;  // a patch off its face: the meshes do not match
  for (Vec3& v : moved.patches[5].v) v += moved.patches[5].normal * 0.05f;
  moved.patches[5].centroid += moved.patches[5].normal * 0.05f;
  EXPECT_EQ(PatchLocator::build(d, moved), nullptr);
  PatchMesh holed = uniform;  // a face with a hole where a patch was: traced as patches, the hole stays open
  holed.patches.erase(holed.patches.begin() + 5);
  EXPECT_EQ(PatchLocator::build(d, holed), nullptr);
}

TEST(PatchLocator, TracingTheFacesFindsTheHitsOfThePatches) {
  const SceneDesc d = room();
  const RenderScene scene(d, tableOf(d));
  ASSERT_TRUE(scene.embree().tracesFaces());
  EXPECT_LT(scene.embree().tracedPolygons(), scene.mesh().size() / 10);
  const EmbreeScene patches(scene.mesh(), scene.lights().emitterMeshes());
  ASSERT_FALSE(patches.tracesFaces());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int rays = 0, same = 0;
  for (; rays < 20000; ++rays) {
    Ray r;
    r.o = Vec3(0.05f + 1.9f * u(rng), 0.55f + 0.9f * u(rng), 0.05f + 1.9f * u(rng));
    const float z = 2.0f * u(rng) - 1.0f, phi = 6.2831853f * u(rng), s = std::sqrt(1.0f - z * z);
    r.d = Vec3(s * std::cos(phi), z, s * std::sin(phi));
    r.tmin = 1e-4f;
    r.tmax = 1e30f;
    Hit a, b;
    const bool fa = scene.embree().intersect(r, a), fb = patches.intersect(r, b);
    ASSERT_EQ(fa, fb) << "ray " << rays;
    if (!fa) continue;
    ASSERT_NEAR(a.t, b.t, 1e-5f * b.t + 1e-6f) << "ray " << rays;
    if (a.patch == b.patch) {
      ++same;
      EXPECT_EQ(a.ng, b.ng);
      continue;
    }
    // A tie on an edge two patches share: both hold the point.
    const Patch& pa = scene.mesh().patches[a.patch];
    const Patch& pb = scene.mesh().patches[b.patch];
    EXPECT_LT(glm::length(a.p - pa.centroid), glm::length(pa.v[0] - pa.centroid) * 1.01f) << "ray " << rays;
    EXPECT_LT(glm::length(b.p - pb.centroid), glm::length(pb.v[0] - pb.centroid) * 1.01f) << "ray " << rays;
  }
  EXPECT_GE(same, rays * 999 / 1000);
}
