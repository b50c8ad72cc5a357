// Patch neighbours (common/patches/patch_neighbours.h): the lists must be exactly the pairs of patches whose
// bounding boxes, grown by 10⁻⁵ of the mesh's diagonal, overlap (ascending, the patch itself left
// out), as an O(n²) test of every pair finds them: on random meshes of mixed sizes, on adaptive
// meshes with T-junctions, and on meshes whose patches crowd one cell.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <random>
#include <vector>

#include "common/patches/patch_neighbours.h"
#include "common/patches/patches.h"
#include "preprocess/adaptive_mesh.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

/// The definition, pair by pair.
PatchNeighbours bruteForce(const PatchMesh& mesh) {
  const uint32_t n = mesh.size();
  std::vector<Vec3> lo(n), hi(n);
  Vec3 sceneLo(INFINITY), sceneHi(-INFINITY);
  for (uint32_t j = 0; j < n; ++j) {
    const Patch& p = mesh.patches[j];
    lo[j] = hi[j] = p.v[0];
    for (uint32_t k = 1; k < p.count; ++k) lo[j] = glm::min(lo[j], p.v[k]), hi[j] = glm::max(hi[j], p.v[k]);
    sceneLo = glm::min(sceneLo, lo[j]), sceneHi = glm::max(sceneHi, hi[j]);
  }
  const float grow = n ? 1e-5f * glm::length(sceneHi - sceneLo) : 0.0f;
  for (uint32_t j = 0; j < n; ++j) lo[j] -= grow, hi[j] += grow;
  PatchNeighbours nb;
  nb.start.push_back(0);
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t k = 0; k < n; ++k)
      if (k != j && glm::all(glm::lessThanEqual(lo[j], hi[k])) && glm::all(glm::lessThanEqual(lo[k], hi[j])))
        nb.adjacent.push_back(k);
    nb.start.push_back(nb.adjacent.size());
  }
  return nb;
}

void expectSameAsBruteForce(const PatchMesh& mesh, const std::string& what) {
  const PatchNeighbours expected = bruteForce(mesh), got = patchNeighbours(mesh);
  ASSERT_EQ(got.start.size(), expected.start.size()) << what;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const std::vector<uint32_t> e(expected.adjacent.begin() + int64_t(expected.start[j]),
                                  expected.adjacent.begin() + int64_t(expected.start[j + 1]));
    const std::vector<uint32_t> g(got.adjacent.begin() + int64_t(got.start[j]), got.adjacent.begin() + int64_t(got.start[j + 1]));
    ASSERT_EQ(g, e) << what << ": patch " << j;
  }
  EXPECT_EQ(got.start, expected.start) << what;
  EXPECT_EQ(got.adjacent, expected.adjacent) << what;
}

Patch makePatch(const std::vector<Vec3>& v) {
  Patch p;
  p.count = uint32_t(v.size());
  for (uint32_t k = 0; k < p.count; ++k) p.v[k] = v[k];
  computePatchGeometry(p);
  return p;
}

/// @p count random triangles and quads, sizes log-uniform over three decades, in a 10 m box; every
/// fourth one shares an edge with the one before, every tenth is a copy of an earlier one.
PatchMesh randomMesh(uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto point = [&](float scale) { return Vec3(u(rng), u(rng), u(rng)) * scale; };
  PatchMesh mesh;
  for (uint32_t j = 0; j < count; ++j) {
    if (j % 10 == 9) {
      mesh.patches.push_back(mesh.patches[std::uniform_int_distribution<uint32_t>(0, j - 1)(rng)]);
      continue;
    }
    const float size = 0.01f * std::pow(1000.0f, u(rng));
    const Vec3 o = j % 4 == 3 ? mesh.patches.back().v[0] : point(10.0f);
    const Vec3 a = j % 4 == 3 ? mesh.patches.back().v[1] - o : (point(2.0f) - 1.0f) * size;
    const Vec3 b = (point(2.0f) - 1.0f) * size;
    mesh.patches.push_back(u(rng) < 0.5f ? makePatch({o, o + a, o + b}) : makePatch({o, o + a, o + a + b, o + b}));
  }
  return mesh;
}

}  // namespace

TEST(PatchNeighbours, EmptyAndSingleMeshes) {
  const PatchNeighbours none = patchNeighbours(PatchMesh());
  EXPECT_EQ(none.start, std::vector<uint64_t>{0});
  EXPECT_TRUE(none.adjacent.empty());
  PatchMesh one;
  one.patches.push_back(makePatch({Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0)}));
  const PatchNeighbours single = patchNeighbours(one);
  EXPECT_EQ(single.start, (std::vector<uint64_t>{0, 0}));
  EXPECT_TRUE(single.adjacent.empty());
}

TEST(PatchNeighbours, RandomMeshesMatchEveryPairTested) {
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    const PatchMesh mesh = randomMesh(seed == 1 ? 200 : 2500, seed);
    expectSameAsBruteForce(mesh, fmt::format("random mesh, seed {}", seed));
  }
}

// Quadtrees over a room with a sphere, split at random for four rounds: patches of five sizes next
// to each other, T-junctions where a split patch meets an unsplit one, the sphere touching the floor.
TEST(PatchNeighbours, AdaptiveMeshesMatchEveryPairTested) {
  const SceneDesc scene = test::sceneFromJson(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [4,2.5,3], "flip_normals": true},
               {"type": "sphere", "material": "white", "center": [2,0.5,1.5], "radius": 0.5, "subdivisions": 2}],
    "lights": [{"type": "point", "position": [2,2,1.5], "power": 10}]})");
  for (uint32_t seed = 1; seed <= 2; ++seed) {
    AdaptiveMesh adaptive(scene, 0.5);
    std::mt19937 rng(seed);
    for (int round = 0; round < 4; ++round) {
      std::vector<uint8_t> split(adaptive.mesh().size());
      for (uint8_t& s : split) s = std::uniform_int_distribution<int>(0, 3)(rng) == 0;
      adaptive.split(split);
    }
    ASSERT_GT(adaptive.mesh().size(), 1000u);
    expectSameAsBruteForce(adaptive.mesh(), fmt::format("adaptive mesh, seed {}, {} patches", seed, adaptive.mesh().size()));
  }
}

// Boxes that touch exactly once grown (lo − grow == hi + grow in float) are neighbours, boxes one
// float step further apart are not: along each axis, from either side.
TEST(PatchNeighbours, BoxesTouchingOnceGrownAreNeighbours) {
  // Two anchors fix the mesh's box to [0, 10]³, so the grow is known.
  const Patch anchors[2] = {makePatch({Vec3(0.0f), Vec3(0.1f, 0.0f, 0.0f), Vec3(0.0f, 0.1f, 0.0f)}),
                            makePatch({Vec3(10.0f), Vec3(9.9f, 10.0f, 10.0f), Vec3(10.0f, 9.9f, 10.0f)})};
  const float grow = 1e-5f * glm::length(Vec3(10.0f));
  int touching = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < 8; ++k) {
      // A ends at h along the axis; B starts at x, the first float with x − grow == h + grow.
      const float h = 2.0f + 0.73f * float(k);
      float x = h + 2.0f * grow;
      while (x - grow > h + grow) x = std::nextafter(x, 0.0f);
      while (x - grow < h + grow) x = std::nextafter(x, INFINITY);
      if (x - grow != h + grow) continue;
      ++touching;
      for (const float start : {x, std::nextafter(x, INFINITY)}) {
        Vec3 a0(5.0f), a1(5.5f), b0(5.2f), b1(5.8f);
        a0[axis] = h - 0.5f, a1[axis] = h, b0[axis] = start, b1[axis] = start + 0.5f;
        Vec3 a2 = a1, b2 = b1;
        a2[(axis + 1) % 3] = a0[(axis + 1) % 3], b2[(axis + 1) % 3] = b0[(axis + 1) % 3];
        PatchMesh mesh;
        mesh.patches = {anchors[0], anchors[1], makePatch({a0, a2, a1}), makePatch({b0, b2, b1})};
        if (k % 2) std::swap(mesh.patches[2], mesh.patches[3]);  // B before A half of the time
        const PatchNeighbours expected = bruteForce(mesh);
        const uint64_t pairs = start == x ? 1 : 0;
        ASSERT_EQ(expected.start[3] - expected.start[2], pairs) << "axis " << axis << ", h " << h;
        expectSameAsBruteForce(mesh, fmt::format("axis {}, h {}, B from {}", axis, h, start));
      }
    }
  EXPECT_GT(touching, 12);
}

// A fan of 300 slivers around one point (all in one cell, each touching every other), the same
// patch 50 times, and large quads over a field of small triangles (a large patch in many cells).
TEST(PatchNeighbours, CrowdedCellsMatchEveryPairTested) {
  PatchMesh fan;
  for (int k = 0; k < 300; ++k) {
    const float a = 2.0f * kPiF * float(k) / 300.0f, b = 2.0f * kPiF * float(k + 1) / 300.0f;
    fan.patches.push_back(makePatch({Vec3(0.0f), Vec3(std::cos(a), 0.0f, std::sin(a)), Vec3(std::cos(b), 0.0f, std::sin(b))}));
  }
  expectSameAsBruteForce(fan, "fan");
  PatchMesh copies;
  for (int k = 0; k < 50; ++k) copies.patches.push_back(makePatch({Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0)}));
  copies.patches.push_back(makePatch({Vec3(2.0f), Vec3(3, 2, 2), Vec3(2, 3, 2)}));
  expectSameAsBruteForce(copies, "copies");
  PatchMesh mixed;
  for (int x = 0; x < 40; ++x)
    for (int z = 0; z < 40; ++z) {
      const Vec3 o(0.05f * float(x), 0.0f, 0.05f * float(z));
      mixed.patches.push_back(makePatch({o, o + Vec3(0.05f, 0.0f, 0.0f), o + Vec3(0.0f, 0.0f, 0.05f)}));
    }
  for (int k = 0; k < 4; ++k) {
    const Vec3 o(0.5f * float(k), 0.0f, 0.3f * float(k));
    mixed.patches.push_back(makePatch({o, o + Vec3(0.7f, 0.0f, 0.0f), o + Vec3(0.7f, 0.0f, 0.7f), o + Vec3(0.0f, 0.0f, 0.7f)}));
  }
  expectSameAsBruteForce(mixed, "large quads over small triangles");
}
