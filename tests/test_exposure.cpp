// ExposureCache (preprocess/exposure.h): which points of a patch are buried under a closed object,
// decided once per lattice cell, the same whatever order (light, thread) asks.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "common/patches.h"
#include "common/scene_desc.h"
#include "preprocess/adaptive_mesh.h"
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

// After a split, a child decides buried points as its parent did (ExposureCache::inherit): the same box
// on a floor of 0.4 m patches, the patches under the box's edges split; every child of a straddling
// patch gives its parent's answers at 21 × 21 points of its own, and an unsplit patch keeps its mask.
TEST(Exposure, ChildrenOfASplitInheritTheirParentsAnswers) {
  const SceneDesc desc = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "box", "material": "white", "min": [-0.3,0,-0.3], "max": [0.3,0.05,0.3]}]})");
  AdaptiveMesh adaptive(desc, 0.4);
  const PatchMesh before = adaptive.mesh();
  Bounds3d bounds;
  for (const Patch& p : before.patches)
    for (uint32_t k = 0; k < p.count; ++k) bounds.extend(Vec3d(p.v[k]));
  const EmbreeItemBuffer raysBefore(ItemGeometry::fromPatches(before), bounds);
  ExposureCache parent(before, raysBefore);
  std::vector<uint8_t> flags(before.size(), 0);
  int partial = 0;
  for (uint32_t j = 0; j < before.size(); ++j)
    if (before.patches[j].shape == 0 && before.patches[j].normal.y > 0 && parent.mask(j, 0).partial)
      flags[j] = 1, ++partial;
  ASSERT_GE(partial, 4);
  const uint32_t keptWhole = std::find(flags.begin(), flags.end(), 0) - flags.begin();
  parent.mask(keptWhole, 0);
  const std::vector<uint32_t> first = adaptive.split(flags);
  const PatchMesh& after = adaptive.mesh();
  const EmbreeItemBuffer raysAfter(ItemGeometry::fromPatches(after), bounds);
  ExposureCache child(after, raysAfter, ExposureCache::inherit(parent.masks(), first));
  EXPECT_EQ(&child.mask(first[keptWhole], 0), &parent.mask(keptWhole, 0));
  int compared = 0, buried = 0;
  for (uint32_t j = 0; j < before.size(); ++j) {
    if (!flags[j]) continue;
    const ExposureQuery asParent{&parent, &parent.mask(j, 0), j, 0};
    for (uint32_t c = first[j]; c < first[j + 1]; ++c) {
      const ExposureQuery asChild{&child, &child.mask(c, 0), c, 0};
      const Patch& p = after.patches[c];
      for (int b = 0; b <= 20; ++b)
        for (int a = 0; a <= 20; ++a) {
          const double u = a / 20.0, v = b / 20.0;
          const Vec3d x = (1 - u) * (1 - v) * Vec3d(p.v[0]) + u * (1 - v) * Vec3d(p.v[1]) + u * v * Vec3d(p.v[2]) +
                          (1 - u) * v * Vec3d(p.v[3]);
          const bool want = asParent.buried(x);
          EXPECT_EQ(asChild.buried(x), want) << "child " << c << " of " << j;
          ++compared, buried += want;
        }
    }
  }
  EXPECT_GT(buried, compared / 10);
  EXPECT_LT(buried, compared * 9 / 10);
}
