// ExposureCache (preprocess/exposure.h): which points of a patch are buried under a closed object,
// decided once per lattice cell, the same whatever order (light, thread) asks.
#include <gtest/gtest.h>

#include <thread>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/exposure.h"
#include "preprocess/item_buffer.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

/// A box standing on a floor of 0.2 m patches, its sides through the middle of patches, and the rays
/// the exposure probes trace through it.
class Exposure : public ::testing::Test {
 protected:
  Exposure() : mesh(buildPatches(scene(), 0.2)), geometry(ItemGeometry::fromPatches(mesh)), rays(geometry, bounds(mesh)) {}

  static SceneDesc scene() {
    return test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
      "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
                 {"type": "box", "material": "white", "min": [-0.3,0,-0.3], "max": [0.3,0.05,0.3]}]})");
  }
  static Bounds3d bounds(const PatchMesh& m) {
    Bounds3d b;
    for (const Patch& p : m.patches)
      for (uint32_t k = 0; k < p.count; ++k) b.extend(Vec3d(p.v[k]));
    return b;
  }

  const PatchMesh mesh;
  const ItemGeometry geometry;
  const EmbreeItemBuffer rays;
};

}  // namespace

// On every floor patch the box half covers: the mask is partial; points farther than a lattice cell's
// diagonal from the box's edge are buried exactly when under the box; and the answers are identical
// when the points are asked in another order from two threads on a second cache.
TEST_F(Exposure, BuriedUnderABoxExactlyAwayFromItsEdgeAndIndependentOfOrder) {
  ExposureCache first(mesh, rays), second(mesh, rays);
  const auto under = [](const Vec3d& x) { return std::abs(x.x) < 0.3 && std::abs(x.z) < 0.3; };
  const auto edgeDistance = [](const Vec3d& x) {
    const double dx = std::abs(std::abs(x.x) - 0.3), dz = std::abs(std::abs(x.z) - 0.3);
    return std::abs(x.x) <= 0.3 && std::abs(x.z) <= 0.3 ? std::min(dx, dz)
           : std::abs(x.x) <= 0.3                      ? dz
           : std::abs(x.z) <= 0.3                      ? dx
                                                       : std::hypot(dx, dz);
  };
  int straddling = 0, decided = 0;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    if (p.shape != 0) continue;
    const Vec3d c(p.centroid);
    if (std::abs(c.x) > 0.4 || std::abs(c.z) > 0.4 || (under(c - Vec3d(0.1, 0, 0.1)) == under(c + Vec3d(0.1, 0, 0.1)) &&
                                                        under(c - Vec3d(0.1, 0, -0.1)) == under(c + Vec3d(0.1, 0, -0.1))))
      continue;  // not cut by the box's edge
    ++straddling;
    const int side = p.normal.y > 0 ? 0 : 1;
    const ExposureMask& m1 = first.mask(j, side);
    const ExposureMask& m2 = second.mask(j, side);
    ASSERT_TRUE(m1.partial) << "patch " << j;
    ASSERT_GT(m1.h, 0.0);
    const ExposureQuery q1{&first, &m1, j, side}, q2{&second, &m2, j, side};
    // 41 × 41 points over the patch's bounding square (corners of the 0.2 m patch at c ± 0.1).
    std::vector<Vec3d> points;
    for (int b = 0; b <= 40; ++b)
      for (int a = 0; a <= 40; ++a) points.push_back(c + Vec3d(-0.1 + 0.005 * a, 0.0, -0.1 + 0.005 * b));
    std::vector<uint8_t> answer1(points.size()), answer2(points.size());
    for (size_t k = 0; k < points.size(); ++k) answer1[k] = q1.buried(points[k]);
    std::thread other([&] {
      for (size_t k = points.size(); k-- > 0;)
        if (k % 2) answer2[k] = q2.buried(points[k]);
    });
    for (size_t k = points.size(); k-- > 0;)
      if (k % 2 == 0) answer2[k] = q2.buried(points[k]);
    other.join();
    EXPECT_EQ(answer1, answer2) << "patch " << j;
    for (size_t k = 0; k < points.size(); ++k) {
      if (edgeDistance(points[k]) <= std::sqrt(2.0) * m1.h) continue;
      ++decided;
      EXPECT_EQ(answer1[k] != 0, under(points[k])) << "patch " << j << " at " << points[k].x << ", " << points[k].z;
    }
  }
  EXPECT_EQ(straddling, 12);  // 2 along each side of the box and the 4 under its corners
  EXPECT_GT(decided, 12 * 1300);
}

// Only a surface that meets a patch can bury part of it: floor patches that touch nothing but the
// floor are decided without probes (no probe points), those the box meets are probed (and partial
// where its edge crosses them, as above).
TEST_F(Exposure, OnlyPatchesMetByAnotherSurfaceAreProbed) {
  ExposureCache cache(mesh, rays);
  int probed = 0, skipped = 0, partial = 0;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    if (p.shape != 0) continue;
    const ExposureMask& m = cache.mask(j, 0);
    // The box's sides stand on the lines |x| = 0.3 (|z| <= 0.3) and |z| = 0.3 (|x| <= 0.3); its bottom
    // lies in the floor's plane and meets nothing. A hair of slack for the grown boxes.
    float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
    for (uint32_t k = 0; k < p.count; ++k)
      lo[0] = std::min(lo[0], p.v[k].x), hi[0] = std::max(hi[0], p.v[k].x), lo[1] = std::min(lo[1], p.v[k].z),
      hi[1] = std::max(hi[1], p.v[k].z);
    const float h = 1e-3f;
    auto crosses = [&](int a, float at) { return lo[a] <= at + h && hi[a] >= at - h; };
    auto within = [&](int a) { return lo[a] <= 0.3f + h && hi[a] >= -0.3f - h; };
    const bool meets = ((crosses(0, 0.3f) || crosses(0, -0.3f)) && within(1)) ||
                       ((crosses(1, 0.3f) || crosses(1, -0.3f)) && within(0));
    EXPECT_EQ(!m.points.empty(), meets) << "patch " << j << " at " << p.centroid.x << ", " << p.centroid.z;
    (m.points.empty() ? skipped : probed)++;
    partial += m.partial;
  }
  EXPECT_EQ(partial, 12);
  EXPECT_GT(skipped, 40);
  EXPECT_EQ(probed, 12);  // the box's sides cross 12 patches and touch no others
}
