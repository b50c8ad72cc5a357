// Patches: areas, normals, size bound, stable IDs and byte-for-byte determinism.
#include <gtest/gtest.h>

#include <cstring>

#include "common/formats/load_scene.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

SceneDesc load(const char* name) { return loadScene(test::source(std::string("scenes/") + name + ".json")); }

double longestEdge(const Patch& p) {
  double e = 0;
  for (uint32_t i = 0; i < p.count; ++i) e = std::max(e, double(glm::length(p.v[(i + 1) % p.count] - p.v[i])));
  return e;
}

}  // namespace

TEST(Patches, AreasSumToSurfaceArea) {
  for (const char* name : {"cornell", "many-lights", "point-over-plane"}) {
    SCOPED_TRACE(name);
    const SceneDesc s = load(name);
    for (double size : {0.3, 0.05}) {
      const PatchMesh mesh = buildPatches(s, size);
      std::vector<double> perShape(s.shapes.size(), 0.0);
      for (const auto& p : mesh.patches) perShape[p.shape] += p.area;
      double surface = 0;
      for (size_t i = 0; i < s.shapes.size(); ++i) {
        if (s.materials[s.shapes[i].material].isEmissive()) {
          EXPECT_EQ(perShape[i], 0.0) << "emitters are not patches";
          continue;
        }
        const double a = shapeArea(s.shapes[i]);
        surface += a;
        EXPECT_NEAR(perShape[i], a, 1e-6 * a) << s.shapes[i].name;
      }
      EXPECT_NEAR(mesh.totalArea(), surface, 1e-6 * surface);
    }
  }
}

TEST(Patches, NoPatchLargerThanPatchSize) {
  const SceneDesc s = load("cornell");
  for (double size : {0.1, 0.025}) {
    const PatchMesh mesh = buildPatches(s, size);
    for (const auto& p : mesh.patches) ASSERT_LE(longestEdge(p), size * (1 + 1e-5));
  }
}

TEST(Patches, NormalsMatchTheSourceFaces) {
  const SceneDesc s = load("cornell");
  const PatchMesh mesh = buildPatches(s, 0.05);
  for (const auto& p : mesh.patches) {
    ASSERT_NEAR(glm::length(p.normal), 1.0f, 1e-6f);
    const std::string& name = s.shapes[p.shape].name;
    if (name.find("floor") != std::string::npos) {
      ASSERT_GT(p.normal.y, 0.9999f);
    }
    if (name.find("ceiling") != std::string::npos) {
      ASSERT_LT(p.normal.y, -0.9999f);
    }
    if (name.find("back wall") != std::string::npos) {
      ASSERT_LT(p.normal.z, -0.9999f);
    }
    if (name.find("right wall") != std::string::npos) {
      ASSERT_GT(p.normal.x, 0.9999f);
    }
    if (name.find("left wall") != std::string::npos) {
      ASSERT_LT(p.normal.x, -0.999f);
    }
    if (name.find("top") != std::string::npos) {
      ASSERT_GT(p.normal.y, 0.9999f);
    }
    // Planar: every vertex lies in the patch's plane.
    for (uint32_t i = 0; i < p.count; ++i) ASSERT_NEAR(glm::dot(p.v[i] - p.centroid, p.normal), 0.0f, 1e-6f);
  }
}

TEST(Patches, BlockSidesFaceOutward) {
  const SceneDesc s = load("cornell");
  const PatchMesh mesh = buildPatches(s, 0.05);
  const Vec3 shortCentre(0.1855f, 0.0825f, 0.169f), tallCentre(0.3685f, 0.165f, 0.3515f);
  for (const auto& p : mesh.patches) {
    const std::string& name = s.shapes[p.shape].name;
    if (name.find("side") == std::string::npos) continue;
    const Vec3 c = name.find("short") != std::string::npos ? shortCentre : tallCentre;
    ASSERT_GT(glm::dot(p.normal, Vec3(p.centroid.x, 0, p.centroid.z) - Vec3(c.x, 0, c.z)), 0.0f) << name;
  }
}

TEST(Patches, TriangleSubdivisionPreservesOrientationAndArea) {
  const Vec3d v[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<std::vector<Vec3d>> out;
  subdividePolygon(v, 3, 0.1, out);
  EXPECT_EQ(out.size(), 15u * 15u);  // longest edge sqrt(2): 15 cells per side
  double area = 0;
  for (const auto& t : out) {
    const Vec3d n = glm::cross(t[1] - t[0], t[2] - t[0]);
    EXPECT_GT(n.z, 0);
    area += 0.5 * glm::length(n);
  }
  EXPECT_NEAR(area, 0.5, 1e-12);
}

TEST(Patches, DeterministicByteForByte) {
  const SceneDesc a = load("many-lights");
  const SceneDesc b = load("many-lights");
  const PatchMesh ma = buildPatches(a, 0.1), mb = buildPatches(b, 0.1);
  ASSERT_EQ(ma.size(), mb.size());
  EXPECT_EQ(hashPatches(ma), hashPatches(mb));
  for (uint32_t i = 0; i < ma.size(); ++i) {
    ASSERT_EQ(std::memcmp(ma.patches[i].v, mb.patches[i].v, sizeof(ma.patches[i].v)), 0);
    ASSERT_EQ(ma.patches[i].area, mb.patches[i].area);
  }
  EXPECT_NE(hashPatches(ma), hashPatches(buildPatches(a, 0.11)));
}

TEST(Patches, IdsAreDenseAndOrderedByShape) {
  const SceneDesc s = load("cornell");
  const PatchMesh mesh = buildPatches(s, 0.05);
  ASSERT_GT(mesh.size(), 0u);
  for (uint32_t i = 1; i < mesh.size(); ++i) ASSERT_LE(mesh.patches[i - 1].shape, mesh.patches[i].shape);
}
