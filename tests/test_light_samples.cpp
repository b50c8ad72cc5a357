// Area-light tessellation (preprocess/light_tessellation.h): exact weights, refinement that follows
// the receivers, the vertex rule's accuracy at the default tolerance, and few samples far from everything.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "preprocess/light_samples.h"
#include "preprocess/light_tessellation.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

SceneDesc sceneFrom(const std::string& json) { return test::sceneFromJson(json); }

/// A 4 × 3 × 4 m room seen from inside plus @p lightShapes (material "lamp") and @p extraShapes.
std::string room(const std::string& lightShapes, const std::string& extraShapes = "") {
  return R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": 1}},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [4,3,4], "flip_normals": true})" +
         extraShapes + "," + lightShapes + "]}";
}

int firstEmissiveShape(const SceneDesc& s) {
  for (size_t i = 0; i < s.shapes.size(); ++i)
    if (s.materials[s.shapes[i].material].isEmissive()) return static_cast<int>(i);
  return -1;
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

double triangleDiameter(const std::array<Vec3d, 3>& t) {
  return std::max({glm::length(t[1] - t[0]), glm::length(t[2] - t[1]), glm::length(t[0] - t[2])});
}

/// Patch centroids and normals of every receiver surface (both sides of two-sided surfaces are the
/// same point; the side facing the light is the one that receives).
std::vector<std::pair<Vec3d, Vec3d>> receiverPoints(const SceneDesc& s, double patchSize) {
  std::vector<std::pair<Vec3d, Vec3d>> pts;
  for (const Patch& p : buildPatches(s, patchSize).patches) {
    pts.emplace_back(Vec3d(p.centroid), Vec3d(p.normal));
    pts.emplace_back(Vec3d(p.centroid), -Vec3d(p.normal));
  }
  return pts;
}

}  // namespace

TEST(LightTessellation, PolygonDistances) {
  const Vec3d sq[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_DOUBLE_EQ(pointPolygonDistance({0.5, 0.5, 2}, sq, 4), 2.0);
  EXPECT_DOUBLE_EQ(pointPolygonDistance({2, 0.5, 0}, sq, 4), 1.0);
  EXPECT_NEAR(pointPolygonDistance({2, 2, 1}, sq, 4), std::sqrt(3.0), 1e-12);
  const Vec3d wall[4] = {{1.5, -1, -1}, {1.5, 2, -1}, {1.5, 2, 1}, {1.5, -1, 1}};
  EXPECT_NEAR(polygonPolygonDistance(sq, 4, wall, 4), 0.5, 1e-12);
  const Vec3d skew[3] = {{0.5, 2, 1}, {0.5, 3, 1}, {0.5, 2.5, 3}};
  EXPECT_NEAR(polygonPolygonDistance(sq, 4, skew, 3), std::sqrt(2.0), 1e-12);
}

// (a) The weights S_i/3 sum to the light's exact area, for several shapes, uniform and automatic, with
// hanging vertices where refinement levels meet. An emissive mesh (the sphere: more than kLightMeshFaces
// faces) has its automatic samples merged into clusters, whose weights keep the power each sends in front
// of its mean normal: the sum lies between (1 − tolerance)·area and the area (preprocess/light_clusters.h).
TEST(LightTessellation, WeightsSumToArea) {
  const std::vector<std::string> lights = {
      R"({"type": "quad", "material": "lamp", "vertices": [[1,2.9,1],[2.05,2.9,1],[2.05,2.9,2.3],[1,2.9,2.3]]})",
      R"({"type": "quad", "material": "lamp", "vertices": [[0.02,2.5,1],[0.02,2.5,2.5],[1.5,2.5,2.1],[1.2,2.5,1]]})",
      R"({"type": "quad", "material": "lamp", "vertices": [[3.99,1,1],[3.99,2,1],[3.99,2,2],[3.99,1,2]]})",
      R"({"type": "box", "material": "lamp", "min": [0.05,2.6,0.05], "max": [0.45,2.7,0.65]})",
      R"({"type": "sphere", "material": "lamp", "center": [2,0.3,2], "radius": 0.25, "subdivisions": 1})",
  };
  for (const std::string& l : lights) {
    SCOPED_TRACE(l);
    SceneDesc s = sceneFrom(room(l, R"(, {"type": "box", "material": "white", "min": [1.5,0,1.5], "max": [2.5,2.0,2.5]})"));
    const int li = firstEmissiveShape(s);
    s.shapes[li].type = ShapeType::Mesh;  // its vertex samples (a sphere's inside it: tests/test_sphere_light.cpp)
    const double area = shapeArea(s.shapes[li]);
    for (double lps : {0.0, 0.1}) {
      const LightTessellation t = tessellateAreaLight(s, li, lps, 0.01);
      const bool clustered = lps == 0 && s.shapes[li].faces.size() > kLightMeshFaces;
      if (clustered) {
        EXPECT_LE(sum(t.weights), area * (1 + 1e-9));
        EXPECT_GE(sum(t.weights), area * (1 - 0.01));
      } else {
        EXPECT_NEAR(sum(t.weights), area, 1e-9 * area);
      }
      double triangles = 0;
      for (const auto& tri : t.triangles) triangles += 0.5 * glm::length(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
      EXPECT_NEAR(triangles, area, 1e-9 * area);
    }
    // The samples carry the weights in float: the same sum to float precision.
    const std::vector<LightSample> samples = makeLightSamples(s, {static_cast<uint32_t>(s.lights.size() - 1)}, 0, 0.01);
    double fsum = 0;
    for (const LightSample& ls : samples) fsum += ls.weight;
    EXPECT_NEAR(fsum, sum(tessellateAreaLight(s, li, 0, 0.01).weights), 1e-6 * area);
  }
}

// (b) A wall 2 cm from one edge of the light: the triangles along that edge are much smaller than
// those along the far edge.
TEST(LightTessellation, FinerNearACloseReceiver) {
  const SceneDesc s = sceneFrom(room(R"({"type": "quad", "material": "lamp", "vertices": [[2,2.9,1],[3,2.9,1],[3,2.9,2],[2,2.9,2]]})",
                                     R"(, {"type": "quad", "material": "white", "vertices": [[3.02,0,0],[3.02,3,0],[3.02,3,4],[3.02,0,4]]})"));
  const LightTessellation t = tessellateAreaLight(s, firstEmissiveShape(s), 0, 0.01, kNoLightSampleBudget);
  double nearMax = 0, farMin = 1e9;
  for (const auto& tri : t.triangles) {
    const double x = (tri[0].x + tri[1].x + tri[2].x) / 3;
    if (x > 2.95) nearMax = std::max(nearMax, triangleDiameter(tri));
    if (x < 2.1) farMin = std::min(farMin, triangleDiameter(tri));
  }
  EXPECT_LE(4 * nearMax, farMin * (1 + 1e-9)) << "near the wall " << nearMax << " m, far from it " << farMin << " m"
                                               << "; " << t.positions.size() << " samples, floor 1/" << t.floorRatio
                                               << ", tolerance " << t.tolerance;
  // And every triangle meets the bound against the receivers, or is at the floor size.
  const Face& f = s.shapes[firstEmissiveShape(s)].faces[0];
  const ShapeDesc& light = s.shapes[firstEmissiveShape(s)];
  const LightReceivers rec(s, light.vertices[f.v[0]], Vec3d(0, -1, 0));
  for (const auto& tri : t.triangles) {
    const double h = triangleDiameter(tri), d = rec.distance(tri.data(), 3);
    EXPECT_TRUE(kVertexRuleErrorConstant * (h / d) * (h / d) <= t.tolerance || h <= std::sqrt(2.0) / t.floorRatio)
        << "h " << h << " d " << d;
  }
}

namespace {

/// At the default tolerance the automatic cut of light shape @p li keeps the vertex rule within it at
/// @p pts with fewer than @p maxSamples samples, and a uniform cut of @p coarse m does not (so the
/// check can fail).
void expectToleranceMet(const SceneDesc& s, int li, const std::vector<std::pair<Vec3d, Vec3d>>& pts, size_t maxSamples,
                        double coarse) {
  const double tol = SettingsDesc{}.lightTolerance;
  const LightTessellation t = tessellateAreaLight(s, li, 0, tol, kNoLightSampleBudget);
  const VertexRuleError e = vertexRuleError(s.shapes[li], t, pts);
  EXPECT_LE(e.uncut, tol);
  EXPECT_LE(e.cut, tol);
  EXPECT_LT(t.positions.size(), maxSamples);
  EXPECT_GT(vertexRuleError(s.shapes[li], tessellateAreaLight(s, li, coarse, tol), pts).uncut, tol)
      << "the check must be able to fail";
}

}  // namespace

// (b') The same light within the default budget: it would take more samples than the budget at 1%, so the
// tolerance is relaxed (and the floor raised) until it fits, and the bound holds for what was reached.
TEST(LightTessellation, BudgetCapsTheSamples) {
  const SceneDesc s = sceneFrom(room(R"({"type": "quad", "material": "lamp", "vertices": [[2,2.9,1],[3,2.9,1],[3,2.9,2],[2,2.9,2]]})",
                                     R"(, {"type": "quad", "material": "white", "vertices": [[3.02,0,0],[3.02,3,0],[3.02,3,4],[3.02,0,4]]})"));
  const int li = firstEmissiveShape(s);
  ASSERT_GT(tessellateAreaLight(s, li, 0, 0.01, kNoLightSampleBudget).positions.size(), kLightSampleBudget);
  testing::internal::CaptureStderr();
  const LightTessellation t = tessellateAreaLight(s, li, 0, 0.01);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_LE(t.positions.size(), kLightSampleBudget);
  EXPECT_GT(t.tolerance, 0.01);
  EXPECT_NE(said.find("light samples at light_tolerance"), std::string::npos) << said;
  const Face& f = s.shapes[li].faces[0];
  const LightReceivers rec(s, s.shapes[li].vertices[f.v[0]], Vec3d(0, -1, 0));
  for (const auto& tri : t.triangles) {
    const double h = triangleDiameter(tri), d = rec.distance(tri.data(), 3);
    EXPECT_TRUE(kVertexRuleErrorConstant * (h / d) * (h / d) <= t.tolerance || h <= std::sqrt(2.0) / t.floorRatio * (1 + 1e-9))
        << "h " << h << " d " << d;
  }
}

// (c) At the default tolerance the vertex rule is within it at the receivers of the metre-scale
// Cornell box (its light 1 cm under the ceiling, which is behind the light and does not count), and a
// too-coarse tessellation is not.
TEST(LightTessellation, DefaultToleranceMetreCornell) {
  SceneDesc s = loadScene(test::source("scenes/cornell-metre.json"));
  const int li = firstEmissiveShape(s);
  const auto pts = receiverPoints(s, 0.25);
  expectToleranceMet(s, li, pts, 200, 0.7);
}

// (c) A light 1 cm under the ceiling of a small room, 10 cm from a wall: the wall is sampled down
// to the light's plane, the ceiling behind the light is ignored.
TEST(LightTessellation, DefaultToleranceUnderCeilingNearWall) {
  const SceneDesc s = sceneFrom(room(R"({"type": "quad", "material": "lamp", "vertices": [[0.1,2.99,1],[0.7,2.99,1],[0.7,2.99,1.6],[0.1,2.99,1.6]]})"));
  const int li = firstEmissiveShape(s);
  std::vector<std::pair<Vec3d, Vec3d>> pts = receiverPoints(s, 0.1);
  for (double y = 2.5; y < 2.99; y += 0.04)  // the wall next to the light, up to its plane
    for (double z = 0.8; z < 1.8; z += 0.1) pts.emplace_back(Vec3d(0, y, z), Vec3d(1, 0, 0));
  expectToleranceMet(s, li, pts, 2000, 0.1);
}

// (d) A light far from everything is one cell: its 4 corners.
TEST(LightTessellation, FarLightFewSamples) {
  const SceneDesc s = sceneFrom(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": 1}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-5,0,-5],[-5,0,5],[5,0,5],[5,0,-5]]},
               {"type": "quad", "material": "lamp", "vertices": [[0,100,0],[1,100,0],[1,100,1],[0,100,1]]}]})");
  EXPECT_EQ(tessellateAreaLight(s, 1, 0, 0.01).positions.size(), 4u);
  EXPECT_LE(tessellateAreaLight(s, 1, 0, 1e-4).positions.size(), 9u);
}

// A receiver touching the light stops at the floor size instead of splitting without end.
TEST(LightTessellation, TouchingReceiverStopsAtFloor) {
  const SceneDesc s = sceneFrom(room(R"({"type": "quad", "material": "lamp", "vertices": [[0,2.5,1],[1,2.5,1],[1,2.5,2],[0,2.5,2]]})"));
  const int li = firstEmissiveShape(s);
  const LightTessellation t = tessellateAreaLight(s, li, 0, 0.01, kNoLightSampleBudget);
  double smallest = 1e9;
  for (const auto& tri : t.triangles) smallest = std::min(smallest, triangleDiameter(tri));
  EXPECT_GE(smallest, std::sqrt(2.0) / kLightMinSizeRatio / 2 * (1 - 1e-9));
  EXPECT_LT(t.positions.size(), 64u * 64u + 200u);
}

// Same input, same samples, byte for byte.
TEST(LightTessellation, Deterministic) {
  const SceneDesc s = loadScene(test::source("scenes/cornell-metre.json"));
  const std::vector<uint32_t> lights = {0};
  const auto a = makeLightSamples(s, lights, 0, 0.0025), b = makeLightSamples(s, lights, 0, 0.0025);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(LightSample)));
}
