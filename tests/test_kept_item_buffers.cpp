// KeptItemBuffers (preprocess/kept_item_buffers.h): item buffers of a coarse mesh brought up to a split
// by the parent's dividing lines agree with buffers rendered over the split mesh, pixel for pixel except
// along the children's shared edges (where the two decide a pixel centre's side in different precision).
#include <gtest/gtest.h>

#include "common/patches/patches.h"
#include "preprocess/adaptive_mesh.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/item_buffer.h"
#include "preprocess/kept_item_buffers.h"
#include "preprocess/window.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

// Quads (floor, back wall, box) and triangles (an icosphere), seen from inside the room.
SceneDesc room() {
  return test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "quad", "material": "white", "vertices": [[-1,0,-1],[1,0,-1],[1,2,-1],[-1,2,-1]]},
               {"type": "box", "material": "white", "min": [-0.5,0,-0.4], "max": [0.1,0.45,0.2]},
               {"type": "sphere", "material": "white", "center": [0.55,0.35,0.3], "radius": 0.3, "subdivisions": 1}]})");
}

Bounds3d boundsOf(const PatchMesh& mesh) {
  Bounds3d b;
  for (const Patch& p : mesh.patches)
    for (uint32_t k = 0; k < p.count; ++k) b.extend(Vec3d(p.v[k]));
  return b;
}

std::vector<std::vector<uint32_t>> render(const PatchMesh& mesh, const Bounds3d& bounds, const std::vector<View>& views) {
  EmbreeItemBuffer rays(ItemGeometry::fromPatches(mesh), bounds);
  std::vector<std::vector<uint32_t>> ids(views.size());
  for (size_t v = 0; v < views.size(); ++v) rays.render(views[v], ids[v]);
  return ids;
}

// Splits every third patch (and, at the second level, every other child), following each split in the
// kept buffers; after each, compares them with a fresh render of the split mesh. A pixel may differ only
// where the kept ID shows within one pixel of it in the fresh render (an edge between children).
void expectFollowsSplits(const std::vector<View>& views, const Bounds3d& windowBounds) {
  const SceneDesc desc = room();
  AdaptiveMesh adaptive(desc, 0.5);
  Bounds3d bounds = boundsOf(adaptive.mesh());
  bounds.extend(windowBounds.lo), bounds.extend(windowBounds.hi);
  KeptItemBuffers kept;
  ASSERT_TRUE(kept.keep(views, render(adaptive.mesh(), bounds, views), 1e-3, size_t(1) << 30));
  EXPECT_TRUE(kept.at(0));
  for (int level = 1; level <= 2; ++level) {
    const uint32_t n = adaptive.mesh().size();
    std::vector<uint8_t> flags(n);
    for (uint32_t j = 0; j < n; ++j) flags[j] = level == 1 ? j % 3 == 0 : j % 2 == 0;
    const std::vector<uint32_t> first = adaptive.split(flags);
    kept.followSplit(views, adaptive.mesh(), first);
    EXPECT_TRUE(kept.at(level));
    std::vector<std::vector<uint32_t>> got;
    kept.unpack(got);
    const auto want = render(adaptive.mesh(), bounds, views);
    size_t shown = 0, differ = 0, splitPixels = 0;
    for (size_t v = 0; v < views.size(); ++v) {
      const int w = views[v].width, h = views[v].height;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const size_t k = size_t(y) * w + x;
          if (want[v][k] == kNoPatch) continue;
          ++shown;
          splitPixels += adaptive.mesh().patches[want[v][k]].area < 0.5 * 0.5 * 0.3;
          if (got[v][k] == want[v][k]) continue;
          ++differ;
          bool nearby = false;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int xx = x + dx, yy = y + dy;
              if (xx >= 0 && yy >= 0 && xx < w && yy < h) nearby |= want[v][size_t(yy) * w + xx] == got[v][k];
            }
          EXPECT_TRUE(nearby) << "level " << level << " view " << v << " pixel " << x << "," << y << ": kept "
                              << got[v][k] << ", rendered " << want[v][k];
        }
    }
    EXPECT_GT(splitPixels, shown / 10) << "the splits must be seen";
    EXPECT_LT(double(differ), 0.005 * double(shown)) << differ << " of " << shown << " pixels differ";
  }
}

}  // namespace

TEST(KeptItemBuffers, PerspectiveViewsFollowSplitsAsARenderOfTheSplitMesh) {
  const Window cube = makeCubeWindow(96);
  const Vec3d eye(0.2, 1.4, 0.6);
  const std::vector<View> views = placeWindow(cube, eye, Framed(glm::normalize(Vec3d(0.3, -1, -0.2))));
  Bounds3d b;
  b.extend(eye);
  expectFollowsSplits(views, b);
}

TEST(KeptItemBuffers, OrthographicViewsFollowSplitsAsARenderOfTheSplitMesh) {
  AdaptiveMesh adaptive(room(), 0.5);
  const Bounds3d bounds = boundsOf(adaptive.mesh());
  const Vec3d direction = glm::normalize(Vec3d(0.4, -1, -0.3));
  const Window ortho = makeOrthoWindow(160, bounds, direction);
  expectFollowsSplits(placeWindow(ortho, bounds.centre(), Framed(direction)), bounds);
}

TEST(KeptItemBuffers, RunsRoundTripAndKeepNothingOverTheBudget) {
  const Window cube = makeCubeWindow(32);
  const std::vector<View> views = placeWindow(cube, Vec3d(0, 1, 0), Framed(Vec3d(0, -1, 0)));
  AdaptiveMesh adaptive(room(), 0.5);
  const auto ids = render(adaptive.mesh(), boundsOf(adaptive.mesh()), views);
  KeptItemBuffers kept;
  ASSERT_TRUE(kept.keep(views, ids, 0.01, size_t(1) << 30));
  std::vector<std::vector<uint32_t>> back;
  kept.unpack(back);
  EXPECT_EQ(back, ids);
  EXPECT_EQ(kept.nearPlane(), 0.01);
  EXPECT_LT(kept.bytes(), 6 * 32 * 32 * sizeof(uint32_t)) << "runs smaller than the pixels";
  EXPECT_FALSE(kept.keep(views, ids, 0.01, kept.bytes() - 1));
  EXPECT_FALSE(kept.at(0));
  EXPECT_EQ(kept.bytes(), 0u);
}
