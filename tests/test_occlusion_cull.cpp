// OcclusionCull (preprocess/occlusion_cull.h): clusters of unseen patches skipped only when a face
// hides them, so that the point tests they replace would all have found them occluded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>

#include "common/patches/patches.h"
#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/item_buffer.h"
#include "preprocess/occlusion_cull.h"
#include "preprocess/view.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

SceneDesc sceneFrom(const std::string& json) { return test::sceneFromJson(json); }

std::set<uint32_t> kept(const OcclusionCull& cull, const Vec3d& eye, const std::vector<uint32_t>& shown) {
  std::vector<uint32_t> out;
  cull.visible(eye, shown, out);
  return {out.begin(), out.end()};
}

}  // namespace

// A wall between the eye and three small quads: the one straight behind it is skipped; the one beside
// it (outside the wall's edge planes), the one in front of it and one just behind its edge are kept.
TEST(OcclusionCull, WallHidesOnlyWhatIsWhollyBehindIt) {
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [
      {"type": "quad", "material": "m", "vertices": [[-1,-1,1],[1,-1,1],[1,1,1],[-1,1,1]], "name": "wall"},
      {"type": "quad", "material": "m", "vertices": [[-0.1,-0.1,3],[0.1,-0.1,3],[0.1,0.1,3],[-0.1,0.1,3]], "name": "behind"},
      {"type": "quad", "material": "m", "vertices": [[4.9,-0.1,3],[5.1,-0.1,3],[5.1,0.1,3],[4.9,0.1,3]], "name": "beside"},
      {"type": "quad", "material": "m", "vertices": [[-0.1,-0.1,0.5],[0.1,-0.1,0.5],[0.1,0.1,0.5],[-0.1,0.1,0.5]], "name": "front"},
      {"type": "quad", "material": "m", "vertices": [[2.9,-0.1,3],[3.1,-0.1,3],[3.1,0.1,3],[2.9,0.1,3]], "name": "edge"}
    ]})");
  const PatchMesh mesh = buildPatches(s, 10.0);
  ASSERT_EQ(mesh.size(), 5u);
  const OcclusionCull cull(s, mesh, 1);
  const std::set<uint32_t> k = kept(cull, Vec3d(0.0), {0});
  EXPECT_EQ(k, (std::set<uint32_t>{0, 2, 3, 4}));
  // Seen from the other side the wall hides the quad in front of it instead; with no shown shape to
  // lend faces nothing is skipped.
  EXPECT_EQ(kept(cull, Vec3d(0, 0, 10), {0}), (std::set<uint32_t>{0, 1, 2, 4}));
  EXPECT_EQ(kept(cull, Vec3d(0.0), {}).size(), 5u);
}

// Property: in a grid of closed rooms, every patch skipped for an eye inside one room is occluded at
// its centroid and at the midpoints towards its vertices (the points the point tests use), by an
// exact Embree ray from the eye; and most patches of the other rooms are skipped.
TEST(OcclusionCull, SkippedPatchesAreOccludedAtEveryTestPoint) {
  std::string shapes;
  for (int r = 0; r < 4; ++r) {
    const double x0 = 5.0 * (r % 2), z0 = 5.0 * (r / 2), x1 = x0 + 4, z1 = z0 + 4;
    auto q = [&](double ax, double ay, double az, double bx, double by, double bz, double cx, double cy, double cz,
                 double dx, double dy, double dz) {
      char buf[512];
      std::snprintf(buf, sizeof buf,
                    R"({"type": "quad", "material": "m", "vertices": [[%g,%g,%g],[%g,%g,%g],[%g,%g,%g],[%g,%g,%g]]},)",
                    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz);
      shapes += buf;
    };
    q(x1, 0, z0, x0, 0, z0, x0, 0, z1, x1, 0, z1);
    q(x1, 3, z0, x1, 3, z1, x0, 3, z1, x0, 3, z0);
    q(x0, 0, z0, x1, 0, z0, x1, 3, z0, x0, 3, z0);
    q(x1, 0, z1, x0, 0, z1, x0, 3, z1, x1, 3, z1);
    q(x0, 0, z1, x0, 0, z0, x0, 3, z0, x0, 3, z1);
    q(x1, 0, z0, x1, 0, z1, x1, 3, z1, x1, 3, z0);
    char box[256];
    std::snprintf(box, sizeof box, R"({"type": "box", "material": "m", "min": [%g,0,%g], "max": [%g,0.8,%g]},)", x0 + 1.2,
                  z0 + 2.2, x0 + 2.0, z0 + 3.0);
    shapes += box;
  }
  shapes.pop_back();
  const SceneDesc s = sceneFrom(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}}, "shapes": [)" + shapes + "]}");
  const PatchMesh mesh = buildPatches(s, 0.25);
  Bounds3d b;
  for (const Patch& p : mesh.patches)
    for (uint32_t k = 0; k < p.count; ++k) b.extend(Vec3d(p.v[k]));
  const EmbreeItemBuffer rays(mesh, b);
  const OcclusionCull cull(s, mesh);
  // Shown: every patch of room 0 (its 6 walls and its box), which a window inside it would see.
  std::vector<uint32_t> room0;
  for (uint32_t j = 0; j < mesh.size(); ++j)
    if (mesh.patches[j].shape < 7) room0.push_back(j);
  uint64_t draws = 0;
  auto uniform = [&] { return bitsToUnitDouble(hashKeys(7, draws++)); };
  size_t skippedTotal = 0, others = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const Vec3d eye(0.3 + 3.4 * uniform(), 1.2 + 1.6 * uniform(), 0.3 + 1.6 * uniform());
    const std::set<uint32_t> k = kept(cull, eye, room0);
    for (uint32_t j = 0; j < mesh.size(); ++j) {
      if (mesh.patches[j].shape >= 7) ++others;
      if (k.count(j)) continue;
      ++skippedTotal;
      const Patch& p = mesh.patches[j];
      const Vec3d c(p.centroid);
      for (uint32_t v = 0; v <= p.count; ++v) {
        const Vec3d x = v == p.count ? c : 0.5 * (c + Vec3d(p.v[v]));
        double t = 0;
        EXPECT_NE(rays.firstHit(eye, x - eye, 1.0 - 1e-5, t), kNoPatch) << "patch " << j << " point " << v;
      }
    }
  }
  EXPECT_GT(skippedTotal, others * 6 / 10);  // most of the other rooms' patches (74% when written)
}
