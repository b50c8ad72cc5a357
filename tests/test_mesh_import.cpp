// Tests of common/mesh_import: OBJ, glTF (embedded, external .bin, GLB) and PLY files written here.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <optional>
#include <sstream>
#include <utility>

#include "common/formats/assets/mesh_import.h"
#include "common/formats/json/scene_json.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

using ::testing::HasSubstr;

double triangleArea(const std::vector<Vec3d>& v, const Face& f) {
  return 0.5 * glm::length(glm::cross(v[f.v[1]] - v[f.v[0]], v[f.v[2]] - v[f.v[0]]));
}
Vec3d triangleNormal(const std::vector<Vec3d>& v, const Face& f) {
  return glm::normalize(glm::cross(v[f.v[1]] - v[f.v[0]], v[f.v[2]] - v[f.v[0]]));
}
void expectNear(const Vec3d& a, const Vec3d& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}
void expectNear(const Color& a, const Color& b, double relTol) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], relTol * std::max(1.0f, std::abs(b[i])));
}

std::string base64(const std::string& bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 2]));
    for (size_t k = 0; k < 4; ++k) out += i + k <= bytes.size() ? abc[(n >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

/// The unit right triangle (0,0,0) (1,0,0) (0,1,0) as 36 bytes of little-endian floats.
std::string triangleBytes() {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

/// glTF buffers/bufferViews/accessors for the triangle, the buffer given by @p bufferUri (none: GLB).
std::string triangleBuffers(const std::string& bufferUri) {
  const std::string uri = bufferUri.empty() ? "" : R"("uri": ")" + bufferUri + R"(", )";
  return R"("buffers": [{)" + uri + R"("byteLength": 36}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}])";
}
std::string embeddedBuffers() { return triangleBuffers("data:application/octet-stream;base64," + base64(triangleBytes())); }

/// A glTF with one triangle mesh under a node with translation and scale.
std::string simpleGltf(const std::string& buffers) {
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "translation": [1, 2, 3], "scale": [2, 3, 4]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], )" + buffers + "}";
}

/// Expects the triangle of simpleGltf(): world-space T(1,2,3)·S(2,3,4) applied.
void expectSimpleTriangle(const MeshData& m) {
  ASSERT_EQ(m.faces.size(), 1u);
  ASSERT_EQ(m.vertices.size(), 3u);
  const Face& f = m.faces[0];
  expectNear(m.vertices[f.v[0]], {1, 2, 3}, 0);
  expectNear(m.vertices[f.v[1]], {3, 2, 3}, 0);
  expectNear(m.vertices[f.v[2]], {1, 5, 3}, 0);
}

TEST(MeshImport, ObjQuadIsTwoTrianglesSharingTheDiagonal) {
  const std::string path = test::tempDir() + "/quad.obj";
  test::writeText(path, "v 0 0 0\nv 2 0 0\nv 2 1.5 0\nv 0 1.5 0\nf 1 2 3 4\n");
  const MeshData m = loadMeshFile(path, "scene.json", "shapes[0]");
  ASSERT_EQ(m.faces.size(), 2u);
  EXPECT_EQ(m.vertices.size(), 4u);
  double area = 0;
  for (const Face& f : m.faces) {
    EXPECT_EQ(f.count, 3);
    area += triangleArea(m.vertices, f);
    expectNear(triangleNormal(m.vertices, f), {0, 0, 1}, 1e-12);
  }
  EXPECT_NEAR(area, 3.0, 3.0 * 1e-9);
}

TEST(MeshImport, ObjCubeIsClosedAndJoined) {
  // Per-face normals make assimp split the corners (24 vertices); joining by position must give 8.
  std::ostringstream obj;  // corner k = 1 + i + 2j + 4k at (0.5, 0.25, -1) + 1.5·(i, j, k)
  for (int k = 0; k < 8; ++k)
    obj << "v " << 0.5 + 1.5 * (k & 1) << " " << 0.25 + 1.5 * ((k >> 1) & 1) << " " << -1.0 + 1.5 * (k >> 2) << "\n";
  obj << "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n";
  const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (int q = 0; q < 6; ++q) {
    obj << "f";
    for (int v : quads[q]) obj << " " << v << "//" << q + 1;
    obj << "\n";
  }
  const std::string path = test::tempDir() + "/cube.obj";
  test::writeText(path, obj.str());
  const MeshData m = loadMeshFile(path, "scene.json", "shapes[1]");
  ASSERT_EQ(m.faces.size(), 12u);
  EXPECT_EQ(m.vertices.size(), 8u);
  double area = 0, volume = 0;
  std::map<std::pair<uint32_t, uint32_t>, int> edges;  // directed edge -> uses
  for (const Face& f : m.faces) {
    area += triangleArea(m.vertices, f);
    volume += glm::dot(m.vertices[f.v[0]], glm::cross(m.vertices[f.v[1]], m.vertices[f.v[2]])) / 6.0;
    for (int k = 0; k < 3; ++k) ++edges[{f.v[k], f.v[(k + 1) % 3]}];
  }
  EXPECT_NEAR(area, 13.5, 13.5 * 1e-9);
  EXPECT_NEAR(volume, 3.375, 3.375 * 1e-9);  // positive: outward winding kept
  EXPECT_EQ(edges.size(), 36u);
  for (const auto& [e, uses] : edges) {  // closed and consistently oriented
    EXPECT_EQ(uses, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
}

TEST(MeshImport, DegenerateTrianglesAreKept) {
  const std::string path = test::tempDir() + "/degenerate.obj";
  test::writeText(path, "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 4\nf 1 2 4\n");
  const MeshData m = loadMeshFile(path, "scene.json", "shapes[0]");
  ASSERT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(triangleArea(m.vertices, m.faces[0]), 0.0);
  EXPECT_EQ(m.faces[1].v[0], m.faces[1].v[1]);
  EXPECT_NEAR(triangleArea(m.vertices, m.faces[2]), 0.5, 1e-15);
}

TEST(MeshImport, GltfEmbeddedExternalAndBinaryAgree) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/embedded.gltf", simpleGltf(embeddedBuffers()));
  test::writeText(dir + "/tri.bin", triangleBytes());
  test::writeText(dir + "/external.gltf", simpleGltf(triangleBuffers("tri.bin")));
  // GLB: header, JSON chunk padded with spaces, BIN chunk (36 bytes, already aligned).
  std::string json = simpleGltf(triangleBuffers(""));
  json.resize((json.size() + 3) / 4 * 4, ' ');
  const std::string bin = triangleBytes();
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  test::writeText(dir + "/binary.glb", "glTF" + u32(2) + u32(uint32_t(12 + 8 + json.size() + 8 + bin.size())) +
                                           u32(uint32_t(json.size())) + "JSON" + json + u32(36) + "BIN" +
                                           std::string(1, '\0') + bin);
  for (const char* name : {"embedded.gltf", "external.gltf", "binary.glb"}) {
    SCOPED_TRACE(name);
    expectSimpleTriangle(loadMeshFile(dir + "/" + name, "scene.json", "shapes[0]"));
  }
}

TEST(MeshImport, PlyAsciiTriangle) {
  const std::string path = test::tempDir() + "/tri.ply";
  test::writeText(path, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n4 0 0\n0 0.5 -2\n3 0 1 2\n");
  const MeshData m = loadMeshFile(path, "scene.json", "shapes[0]");
  ASSERT_EQ(m.faces.size(), 1u);
  expectNear(m.vertices[m.faces[0].v[1]], {4, 0, 0}, 0);
  expectNear(m.vertices[m.faces[0].v[2]], {0, 0.5, -2}, 0);
}

/// A glTF scene: an emissive triangle and a mirrored copy without material under a translated parent,
/// a glossy one (KHR_materials_ior), point, spot and directional lights, a rotated camera, and two extensions
/// the import does not read (clearcoat, sheen).
std::string sceneGltf() {
  return R"({"asset": {"version": "2.0"}, "scene": 0,
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior",
                     "KHR_materials_clearcoat", "KHR_materials_sheen"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "color": [1, 0.5, 0.25], "intensity": 10},
    {"type": "spot", "intensity": 5, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
    {"type": "directional", "intensity": 3}]}},
  "scenes": [{"nodes": [0, 3, 4, 5, 6, 7]}],
  "nodes": [{"name": "parent", "translation": [1, 2, 3], "children": [1, 2]},
    {"mesh": 0, "scale": [2, 3, 4]},
    {"mesh": 1, "scale": [-1, 1, 1]},
    {"mesh": 2},
    {"name": "bulb", "translation": [0, 5, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"translation": [1, 4, 0], "rotation": [-0.70710678, 0, 0, 0.70710678],
     "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"rotation": [-0.70710678, 0, 0, 0.70710678], "extensions": {"KHR_lights_punctual": {"light": 2}}},
    {"translation": [0, 1, 5], "rotation": [0, 0.70710678, 0, 0.70710678], "camera": 0}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}],
  "meshes": [{"name": "lamp", "primitives": [{"attributes": {"POSITION": 0}, "material": 0}]},
    {"name": "plain", "primitives": [{"attributes": {"POSITION": 0}}]},
    {"primitives": [{"attributes": {"POSITION": 0}, "material": 1}]}],
  "materials": [{"name": "Lamp", "emissiveFactor": [1, 0.5, 0.25],
      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
      "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.5, 0.25, 1], "metallicFactor": 0}},
    {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
     "extensions": {"KHR_materials_ior": {"ior": 1.33}, "KHR_materials_clearcoat": {"clearcoatFactor": 1}}}],
  )" + embeddedBuffers() + "}";
}

TEST(MeshImport, GltfSceneShapesAndMaterials) {
  const std::string path = test::tempDir() + "/scene.gltf";
  test::writeText(path, sceneGltf());
  testing::internal::CaptureStderr();
  const SceneDesc s = importAssetScene(path);
  const std::string err = testing::internal::GetCapturedStderr();
  // The extensions that change appearance but are not read: named once, on one line.
  EXPECT_EQ(err, path + ": glTF extensions not supported, ignored: KHR_materials_clearcoat, KHR_materials_sheen\n");
  EXPECT_EQ(s.file, path);
  ASSERT_EQ(s.shapes.size(), 3u);
  for (const ShapeDesc& shape : s.shapes) {
    EXPECT_EQ(shape.type, ShapeType::Mesh);
    EXPECT_EQ(shape.sourceFile, path);
    ASSERT_GE(shape.material, 0);
    ASSERT_LT(shape.material, int(s.materials.size()));
    ASSERT_EQ(shape.faces.size(), 1u);
  }
  EXPECT_EQ(s.shapes[0].name, "lamp");
  expectSimpleTriangle(MeshData{s.shapes[0].vertices, s.shapes[0].faces});
  const MaterialDesc& lamp = s.materials[s.shapes[0].material];
  EXPECT_EQ(lamp.name, "Lamp");
  EXPECT_EQ(lamp.type, MaterialType::Pbr);  // metallic 0, roughness 1 (default)
  expectNear(lamp.albedo, {0.75f, 0.5f, 0.25f}, 1e-6);
  EXPECT_EQ(lamp.metallic, 0.0f);
  EXPECT_EQ(lamp.roughness, 1.0f);
  EXPECT_EQ(lamp.ior, 1.5f);
  expectNear(lamp.emission, {4.0f, 2.0f, 1.0f}, 1e-6);  // emissiveFactor · emissiveStrength
  // Mirrored (scale −1 in x): the winding is reversed so the front stays +z.
  EXPECT_EQ(s.shapes[1].name, "plain");
  expectNear(triangleNormal(s.shapes[1].vertices, s.shapes[1].faces[0]), {0, 0, 1}, 1e-12);
  const MaterialDesc& plain = s.materials[s.shapes[1].material];
  EXPECT_EQ(plain.type, MaterialType::Diffuse);
  expectNear(plain.albedo, Color(0.5f), 0);
  EXPECT_FALSE(plain.isEmissive());
  const MaterialDesc& shiny = s.materials[s.shapes[2].material];
  EXPECT_EQ(shiny.type, MaterialType::Pbr);
  EXPECT_EQ(shiny.metallic, 0.0f);
  EXPECT_EQ(shiny.roughness, 0.5f);
  EXPECT_EQ(shiny.ior, 1.33f);  // KHR_materials_ior
  expectNear(shiny.albedo, Color(0.5f), 1e-6);
  EXPECT_EQ(s.materials.size(), 3u);
}

TEST(MeshImport, GltfLightsAndCamera) {
  const std::string path = test::tempDir() + "/scene.gltf";
  test::writeText(path, sceneGltf());
  const SceneDesc s = importAssetScene(path);
  ASSERT_EQ(s.lights.size(), 3u);
  const LightDesc &point = s.lights[0], &spot = s.lights[1], &sun = s.lights[2];
  EXPECT_EQ(point.type, LightType::Point);
  EXPECT_THAT(point.name, HasSubstr("bulb"));  // assimp names lights by their node
  expectNear(point.position, {0, 5, 0}, 0);
  // Photometric: candela and lux over K = 179 lm/W, the colour multiplying the intensity.
  expectNear(point.power, Color(1.0f, 0.5f, 0.25f) * float(4.0 * kPi * 10.0 / 179.0), 1e-6);
  EXPECT_EQ(spot.type, LightType::Spot);
  expectNear(spot.position, {1, 4, 0}, 1e-12);
  expectNear(spot.direction, {0, -1, 0}, 1e-6);
  EXPECT_NEAR(spot.innerAngleDeg, 0.2 * 180 / kPi, 1e-5);
  EXPECT_NEAR(spot.outerAngleDeg, 0.5 * 180 / kPi, 1e-5);
  // Power = ∫ I·smoothstep(cos θo, cos θi, cos θ) dω, integrated numerically (midpoint rule in cos θ).
  const double ci = std::cos(0.2), co = std::cos(0.5);
  const int n = 100000;
  double integral = 0;
  for (int k = 0; k < n; ++k) {
    const double c = -1.0 + (k + 0.5) * 2.0 / n, t = std::clamp((c - co) / (ci - co), 0.0, 1.0);
    integral += 2.0 * kPi * (t * t * (3 - 2 * t)) * 2.0 / n;
  }
  EXPECT_NEAR(spot.power.x, 5.0 * integral / 179.0, 5.0 * integral / 179.0 * 1e-5);
  EXPECT_EQ(sun.type, LightType::Directional);
  expectNear(sun.direction, {0, -1, 0}, 1e-6);
  expectNear(sun.irradiance, Color(3.0f / 179.0f), 1e-6);
  // Camera: at the node origin (not twice its translation), looking along the rotated −z.
  EXPECT_TRUE(s.camera.given);
  expectNear(s.camera.position, {0, 1, 5}, 1e-12);
  expectNear(s.camera.lookAt, {-1, 1, 5}, 1e-6);
  expectNear(s.camera.up, {0, 1, 0}, 1e-6);
  EXPECT_NEAR(s.camera.fovYDeg, 0.8 * 180 / kPi, 1e-4);
  EXPECT_EQ(s.camera.width, 768);
  EXPECT_EQ(s.camera.height, 512);
}

TEST(MeshImport, ObjSceneWithMtlAndNoCamera) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/m.mtl", "newmtl wall\nKd 0.25 0.5 0.75\nnewmtl lamp\nKd 0.7 0.2 0.1\nKe 5 4 3\n");
  test::writeText(dir + "/m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                  "o wall\nusemtl wall\nf 1 2 4\no lit\nusemtl lamp\nf 1 2 3\n");
  const SceneDesc s = importAssetScene(dir + "/m.obj");
  EXPECT_FALSE(s.camera.given);
  EXPECT_TRUE(s.lights.empty());
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].name, "wall");
  const MaterialDesc& wall = s.materials.at(s.shapes[0].material);
  EXPECT_EQ(wall.name, "wall");
  expectNear(wall.albedo, {0.25f, 0.5f, 0.75f}, 1e-6);
  EXPECT_FALSE(wall.isEmissive());
  const MaterialDesc& lamp = s.materials.at(s.shapes[1].material);
  EXPECT_EQ(lamp.name, "lamp");
  expectNear(lamp.albedo, {0.7f, 0.2f, 0.1f}, 1e-6);
  expectNear(lamp.emission, {5.0f, 4.0f, 3.0f}, 1e-6);
}

TEST(MeshImport, ObjWithoutMaterialsGetsDefaultGrey) {
  const std::string path = test::tempDir() + "/plain.obj";
  test::writeText(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const SceneDesc s = importAssetScene(path);
  ASSERT_EQ(s.shapes.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.shapes[0].material, 0);
  EXPECT_EQ(s.materials[0].type, MaterialType::Diffuse);
  expectNear(s.materials[0].albedo, Color(0.5f), 0);  // not assimp's 0.6 "DefaultMaterial"
  EXPECT_FALSE(s.materials[0].isEmissive());
}

TEST(MeshImport, MissingFileNamesFileAndElement) {
  const std::string path = test::tempDir() + "/nope.obj";
  try {
    loadMeshFile(path, "scenes/box.json", "shapes[2].file");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "scenes/box.json");
    EXPECT_EQ(e.element(), "shapes[2].file");
    EXPECT_THAT(e.what(), HasSubstr(path));
    EXPECT_THAT(e.what(), HasSubstr("scenes/box.json: shapes[2].file: "));
    EXPECT_THAT(e.what(), HasSubstr("not found"));
  }
  EXPECT_THROW(importAssetScene(path), InputError);
}

/// The message of the InputError thrown by loading @p text as @p name.
std::string loadError(const std::string& name, const std::string& text) {
  const std::string path = test::tempDir() + "/" + name;
  test::writeText(path, text);
  try {
    loadMeshFile(path, "s.json", "shapes[0]");
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path));
    return e.what();
  }
  ADD_FAILURE() << name << " loaded without error";
  return {};
}

TEST(MeshImport, MalformedFilesAreInputErrors) {
  EXPECT_THAT(loadError("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), HasSubstr("index out of range"));
  EXPECT_THAT(loadError("syntax.gltf", R"({"asset": {"version": "2.0"}, "nodes": [)"), HasSubstr("parse error"));
  std::string tooLong = simpleGltf(embeddedBuffers());
  tooLong.replace(tooLong.find(R"("count": 3)"), 10, R"("count": 30)");
  EXPECT_THAT(loadError("accessor.gltf", tooLong), HasSubstr("out of range"));
  EXPECT_THAT(loadError("nobin.gltf", simpleGltf(triangleBuffers("missing.bin"))), HasSubstr("missing.bin"));
}

TEST(MeshImport, FilesWithoutTrianglesAreInputErrors) {
  EXPECT_THAT(loadError("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), HasSubstr("no triangles"));
  EXPECT_THAT(loadError("line.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n"), HasSubstr("no triangles"));
  std::string lines = simpleGltf(embeddedBuffers());
  lines.replace(lines.find(R"("attributes")"), 0, R"("mode": 1, )");
  EXPECT_THAT(loadError("lines.gltf", lines), HasSubstr("no triangles"));
  const std::string path = test::tempDir() + "/points.obj";
  test::writeText(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_THROW(importAssetScene(path), InputError);
}

TEST(MeshImport, GltfLightsMatchTheJsonCandela) {
  // KHR_lights_punctual: point and spot intensity in cd, directional in lx, converted as the JSON's "candela".
  const std::string path = test::tempDir() + "/lights.gltf";
  test::writeText(path, R"({"asset": {"version": "2.0"}, "scene": 0, "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 1000},
    {"type": "spot", "intensity": 1000, "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}},
    {"type": "directional", "intensity": 1000}]}},
  "scenes": [{"nodes": [0, 1, 2, 3]}],
  "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"extensions": {"KHR_lights_punctual": {"light": 1}}}, {"extensions": {"KHR_lights_punctual": {"light": 2}}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], )" + embeddedBuffers() + "}");
  const SceneDesc gltf = importAssetScene(path);
  ASSERT_EQ(gltf.lights.size(), 3u);
  const double degrees = 180.0 / kPi;
  SceneDesc json = parseSceneJson(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}],
    "lights": [{"type": "point", "position": [0, 0, 0], "candela": 1000},
               {"type": "spot", "position": [0, 0, 0], "direction": [0, 0, -1], "candela": 1000,
                "inner_angle": )" + std::to_string(gltf.lights[1].innerAngleDeg) + R"(, "outer_angle": )" +
                                      std::to_string(gltf.lights[1].outerAngleDeg) + "}]}", "lights.json");
  EXPECT_NEAR(gltf.lights[1].innerAngleDeg, 0.25 * degrees, 1e-5);
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k == 0 ? "point" : "spot");
    EXPECT_EQ(gltf.lights[k].type, json.lights[k].type);
    expectNear(gltf.lights[k].power, json.lights[k].power, 1e-6);  // float rounding (and the printed angles)
    EXPECT_GT(json.lights[k].power.x, 0.0f);
  }
  EXPECT_NEAR(json.lights[0].power.x, 1000.0 * 4.0 * kPi / 179.0, 1e-6 * json.lights[0].power.x);
  // Directional: E = lux / K W/m² (the JSON gives irradiance in W/m² only).
  EXPECT_EQ(gltf.lights[2].type, LightType::Directional);
  expectNear(gltf.lights[2].irradiance, Color(float(1000.0 / 179.0)), 1e-6);
}

/// simpleGltf() with its buffer in the file tri.bin, which holds @p bin (none: no such file), loaded as a JSON scene's
/// mesh and as a scene; @return the latter's message. Both name the buffer file.
std::string bufferError(const std::optional<std::string>& bin) {
  const std::string dir = test::tempDir();
  if (bin) test::writeText(dir + "/tri.bin", *bin);
  test::writeText(dir + "/tri.gltf", simpleGltf(triangleBuffers("tri.bin")));
  try {
    loadMeshFile(dir + "/tri.gltf", "s.json", "shapes[0].file");
    ADD_FAILURE() << "loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.element(), "shapes[0].file");
    EXPECT_THAT(e.what(), HasSubstr("mesh file " + dir + "/tri.gltf: buffer file " + dir + "/tri.bin "));
  }
  try {
    importAssetScene(dir + "/tri.gltf");
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir + "/tri.gltf");
    EXPECT_THAT(e.what(), HasSubstr("buffer file " + dir + "/tri.bin "));
    return e.what();
  }
  ADD_FAILURE() << "loaded";
  return "";
}

TEST(MeshImport, BrokenGltfBufferIsNamed) {
  EXPECT_THAT(bufferError("version https://git-lfs.github.com/spec/v1\noid sha256:4d7a\nsize 36\n"),
              HasSubstr("tri.bin is a Git LFS pointer, not the data: fetch it with git lfs pull"));
  EXPECT_THAT(bufferError(triangleBytes().substr(0, 20)), HasSubstr("tri.bin has 20 bytes, the glTF says 36"));
  EXPECT_THAT(bufferError(std::nullopt), HasSubstr("tri.bin is missing"));
  EXPECT_THAT(loadError("short.gltf", simpleGltf(triangleBuffers("data:application/octet-stream;base64," +
                                                                 base64(triangleBytes().substr(0, 24))))),
              HasSubstr("buffers[0] (data URI) has 24 bytes, the glTF says 36"));
  EXPECT_THAT(loadError("lfs.obj", "version https://git-lfs.github.com/spec/v1\noid sha256:4d7a\nsize 99\n"),
              HasSubstr("is a Git LFS pointer"));
}

// OBJ/MTL's Phong highlight (illum 2: Ks, Ns) becomes the glossy material, the MTL's own model; illum 1 (no highlight)
// stays diffuse; Kd + Ks above 1 is scaled down to 1.
TEST(MeshImport, ObjPhongHighlightIsGlossy) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/m.mtl",
                  "newmtl shiny\nKd 0.5 0.4 0.3\nKs 0.3 0.3 0.3\nNs 50\nillum 2\n"
                  "newmtl matte\nKd 0.5 0.4 0.3\nKs 0.3 0.3 0.3\nNs 50\nillum 1\n"
                  "newmtl bright\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nNs 10\nillum 2\n");
  test::writeText(dir + "/m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                  "o a\nusemtl shiny\nf 1 2 3\no b\nusemtl matte\nf 1 2 4\no c\nusemtl bright\nf 1 3 4\n");
  const SceneDesc s = importAssetScene(dir + "/m.obj");
  ASSERT_EQ(s.shapes.size(), 3u);
  const MaterialDesc& shiny = s.materials.at(s.shapes[0].material);
  EXPECT_EQ(shiny.type, MaterialType::Glossy);
  expectNear(shiny.albedo, {0.5f, 0.4f, 0.3f}, 1e-6);
  expectNear(shiny.specular, {0.3f, 0.3f, 0.3f}, 1e-6);
  EXPECT_FLOAT_EQ(shiny.exponent, 50.0f);
  EXPECT_EQ(s.materials.at(s.shapes[1].material).type, MaterialType::Diffuse);
  const MaterialDesc& bright = s.materials.at(s.shapes[2].material);
  EXPECT_EQ(bright.type, MaterialType::Glossy);
  expectNear(bright.albedo, {0.8f / 1.3f, 0.8f / 1.3f, 0.8f / 1.3f}, 1e-6);
  expectNear(bright.specular, {0.5f / 1.3f, 0.5f / 1.3f, 0.5f / 1.3f}, 1e-6);
}

}  // namespace
}  // namespace firstshot
