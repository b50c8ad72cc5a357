// ExposureCache (preprocess/exposure.h): which points of a patch are buried under a closed object,
// decided once per lattice cell, the same whatever order (light, thread) asks.
#include <gtest/gtest.h>

#include <thread>

#include "common/patches.h"
#include "common/scene_desc.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/exposure.h"
#include "preprocess/item_buffer.h"
#include "tests/render_util.h"

using namespace fs;

// A box standing on a floor of 0.2 m patches, its sides through the middle of patches. On every floor
// patch it half covers: the mask is partial; points farther than a lattice cell's diagonal from the
// box's edge are buried exactly when under the box; and the answers are identical when the points are
// asked in another order from two threads on a second cache.
TEST(Exposure, BuriedUnderABoxExactlyAwayFromItsEdgeAndIndependentOfOrder) {
  const SceneDesc desc = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "box", "material": "white", "min": [-0.3,0,-0.3], "max": [0.3,0.05,0.3]}]})");
  const PatchMesh mesh = buildPatches(desc, 0.2);
  const ItemGeometry geometry = ItemGeometry::fromPatches(mesh);
  Bounds3d bounds;
  for (const Patch& p : mesh.patches)
    for (uint32_t k = 0; k < p.count; ++k) bounds.extend(Vec3d(p.v[k]));
  const EmbreeItemBuffer rays(geometry, bounds);
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
