// Shipped scenes: every JSON scene in scenes/ loads, validates and splits into patches, and the
// fixture-room, office-floor and cornell-metre scenes have the properties they were made for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/patches/patch_size.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// Every .json file in scenes/, sorted.
std::vector<std::string> shippedJsonScenes() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(test::source("scenes")))
    if (entry.is_regular_file() && entry.path().extension() == ".json") paths.push_back(entry.path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}

/// The scene's triangles that block light: every face of every non-emissive shape (planar quads as two triangles).
struct Triangle {
  Vec3d a, b, c;
};

std::vector<Triangle> occluders(const SceneDesc& scene) {
  std::vector<Triangle> tris;
  for (const ShapeDesc& shape : scene.shapes) {
    if (scene.materials[shape.material].isEmissive()) continue;
    for (const Face& f : shape.faces) {
      const auto& v = shape.vertices;
      tris.push_back({v[f.v[0]], v[f.v[1]], v[f.v[2]]});
      if (f.count == 4) tris.push_back({v[f.v[0]], v[f.v[2]], v[f.v[3]]});
    }
  }
  return tris;
}

/// True when the open segment from @p p to @p q crosses a triangle (Möller–Trumbore, both sides);
/// hits within 1e-6 of either end do not count.
bool segmentBlocked(const std::vector<Triangle>& tris, const Vec3d& p, const Vec3d& q) {
  const Vec3d d = q - p;
  for (const Triangle& t : tris) {
    const Vec3d e1 = t.b - t.a, e2 = t.c - t.a;
    const Vec3d h = glm::cross(d, e2);
    const double det = glm::dot(e1, h);
    if (std::abs(det) < 1e-15) continue;  // segment parallel to the triangle's plane
    const double inv = 1.0 / det;
    const Vec3d s = p - t.a;
    const double u = glm::dot(s, h) * inv;
    if (u < 0 || u > 1) continue;
    const Vec3d qv = glm::cross(s, e1);
    const double w = glm::dot(d, qv) * inv;
    if (w < 0 || u + w > 1) continue;
    const double tt = glm::dot(e2, qv) * inv;
    if (tt > 1e-6 && tt < 1 - 1e-6) return true;
  }
  return false;
}

int countType(const SceneDesc& s, LightType type) {
  return static_cast<int>(std::count_if(s.lights.begin(), s.lights.end(), [&](const LightDesc& l) { return l.type == type; }));
}

}  // namespace

TEST(ShippedScenes, EveryJsonSceneLoadsAndSplitsIntoPatches) {
  const auto paths = shippedJsonScenes();
  EXPECT_GE(paths.size(), 8u) << "cornell, cornell-metre, fixture-room, many-lights, office-floor, point-over-plane, ...";
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    SceneDesc s;
    ASSERT_NO_THROW(s = loadScene(path));  // parses and validates
    EXPECT_FALSE(s.shapes.empty());
    EXPECT_TRUE(!s.lights.empty() || s.sky) << "a light or a sky (daylit-office-overcast has only its sky)";
    EXPECT_TRUE(s.camera.given) << "shipped scenes set their camera";
    const PatchMesh mesh = buildPatches(s, resolvePatchSize(s));
    EXPECT_GT(mesh.size(), 0u);
    EXPECT_LE(mesh.size(), 300000u) << "patch_size keeps the shipped scenes small";
  }
}

TEST(ShippedScenes, FixtureRoomHidesEveryBulb) {
  const SceneDesc s = loadScene(test::source("scenes/fixture-room.json"));
  ASSERT_FALSE(s.lights.empty());
  EXPECT_EQ(countType(s, LightType::Point), static_cast<int>(s.lights.size())) << "only point lights (no area lights)";
  EXPECT_LE(buildPatches(s, resolvePatchSize(s)).size(), 60000u);

  const std::vector<Triangle> tris = occluders(s);
  int cove = 0;
  for (const LightDesc& light : s.lights) {
    SCOPED_TRACE(light.name);
    EXPECT_TRUE(segmentBlocked(tris, s.camera.position, light.position)) << "the camera sees this bulb";
    if (light.name.find("cove bulb") == std::string::npos) continue;
    ++cove;
    // A cove bulb is hidden from every point of the room below the cove's shelf (2.57 m).
    Vec3d lo, hi;
    s.bounds(lo, hi);
    for (int i = 0; i < 10; ++i)
      for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 4; ++j) {
          const Vec3d p(lo.x + 0.2 + (hi.x - lo.x - 0.4) * i / 9.0, 0.1 + 0.8 * j, lo.z + 0.2 + (hi.z - lo.z - 0.4) * k / 7.0);
          ASSERT_TRUE(segmentBlocked(tris, p, light.position)) << "seen from " << p.x << ", " << p.y << ", " << p.z;
        }
  }
  EXPECT_GE(cove, 8);
  EXPECT_LE(cove, 16);
}

TEST(ShippedScenes, OfficeFloorHasHundredsOfMostlyHiddenLights) {
  const SceneDesc s = loadScene(test::source("scenes/office-floor.json"));
  const int points = countType(s, LightType::Point), spots = countType(s, LightType::Spot);
  EXPECT_EQ(points + spots, static_cast<int>(s.lights.size())) << "only point and spot lights";
  EXPECT_GE(points + spots, 200);
  EXPECT_GT(points, 0);
  EXPECT_GT(spots, 0);
  Vec3d lo, hi;
  s.bounds(lo, hi);
  EXPECT_NEAR(hi.x - lo.x, 40.0, 1e-9);
  EXPECT_NEAR(hi.z - lo.z, 20.0, 1e-9);
  EXPECT_NEAR(hi.y - lo.y, 3.0, 1e-9);
  EXPECT_LE(buildPatches(s, resolvePatchSize(s)).size(), 300000u);

  // Walls hide most lights from the camera.
  const std::vector<Triangle> tris = occluders(s);
  int visible = 0;
  for (const LightDesc& light : s.lights) visible += segmentBlocked(tris, s.camera.position, light.position) ? 0 : 1;
  EXPECT_GT(visible, 0);
  EXPECT_LT(visible, static_cast<int>(s.lights.size()) / 5);
}

TEST(ShippedScenes, CornellMetreIsCornellScaledByTen) {
  const SceneDesc small = loadScene(test::source("scenes/cornell.json"));
  const SceneDesc big = loadScene(test::source("scenes/cornell-metre.json"));
  Vec3d lo, hi, bigLo, bigHi;
  small.bounds(lo, hi);
  big.bounds(bigLo, bigHi);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(bigLo[a], 10 * lo[a], 1e-9);
    EXPECT_NEAR(bigHi[a], 10 * hi[a], 1e-9);
  }
  ASSERT_EQ(big.shapes.size(), small.shapes.size());
  for (size_t i = 0; i < big.shapes.size(); ++i) {
    const ShapeDesc& sb = big.shapes[i];
    const ShapeDesc& ss = small.shapes[i];
    if (big.materials[sb.material].isEmissive()) continue;
    SCOPED_TRACE(sb.name);
    ASSERT_EQ(sb.vertices.size(), ss.vertices.size());
    for (size_t k = 0; k < sb.vertices.size(); ++k)
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(sb.vertices[k][a], 10 * ss.vertices[k][a], 1e-9);
  }

  // One area light, 1.30 m x 1.05 m, facing down 1 cm under the ceiling (5.488 m), with cornell's radiance.
  ASSERT_EQ(big.lights.size(), 1u);
  ASSERT_EQ(big.lights[0].type, LightType::Area);
  const ShapeDesc& light = big.shapes[big.lights[0].shape];
  EXPECT_NEAR(shapeArea(light), 1.30 * 1.05, 1e-9);
  for (const auto& v : light.vertices) EXPECT_NEAR(v.y, 5.478, 1e-12);
  EXPECT_EQ(big.materials[light.material].emission, small.materials[small.shapes[small.lights[0].shape].material].emission);

  EXPECT_NEAR(big.camera.position.z, 10 * small.camera.position.z, 1e-9);
  EXPECT_NEAR(big.camera.fovYDeg, small.camera.fovYDeg, 1e-12);
  // Patches from 0.4 m refined to 0.05 m where shadows cross them; the light cut automatically.
  EXPECT_DOUBLE_EQ(big.settings.patchSize, 0.4);
  EXPECT_DOUBLE_EQ(big.settings.minPatchSize, 0.0);
  EXPECT_DOUBLE_EQ(big.settings.lightPatchSize, 0.0);
  EXPECT_DOUBLE_EQ(big.settings.lightTolerance, 0.02);
}
