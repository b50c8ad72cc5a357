// Normal maps as asset files give them: glTF's TANGENT attribute is the tangent frame a normal map tilts
// in (instead of the one generated from the texture coordinates), through a whole-asset scene and a JSON mesh shape
// with a mirroring transform; an OBJ/MTL's `norm` image is the material's normal map, and its `bump` / `map_bump`
// height maps are named once on stderr.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "render/output/image_io.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// The unit tangent-space normal tilted by @p degrees from +z towards tangent-space +x (@p towardsY: +y).
Vec3 tilted(float degrees, bool towardsY) {
  const float t = glm::radians(degrees);
  return towardsY ? Vec3(0, std::sin(t), std::cos(t)) : Vec3(std::sin(t), 0, std::cos(t));
}

/// A normal map of one texel, the tangent-space unit normal @p n (texel (n + 1)/2, linear).
std::shared_ptr<const Texture> constantNormalMap(const Vec3& n) {
  auto t = std::make_shared<Texture>();
  t->image = std::make_shared<const TexelImage>(makeTexelImage(1, 1, {(n + Vec3(1.0f)) * 0.5f}, "tilt"));
  return t;
}

/// Writes, in a fresh directory, the glTF quad y = 0, x and z in [−1, 1], front +y, as two triangles with POSITION,
/// NORMAL (+y), TEXCOORD_0 u = (z + 1)/2, v = (1 − x)/2 (the generated frame: ∂p/∂u = +z, the image's up +x) and
/// TANGENT (1, 0, 0, @p w): the file's tangent +x and bitangent w·N×T = (0, 0, −w), both unlike the generated ones.
/// @return the .gltf's path.
std::string writeTangentQuad(float w) {
  const std::vector<float> positions = {-1, 0, -1, -1, 0, 1, 1, 0, 1, 1, 0, -1};
  const std::vector<float> normals = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  const std::vector<float> tangents = {1, 0, 0, w, 1, 0, 0, w, 1, 0, 0, w, 1, 0, 0, w};
  std::vector<float> uv;
  for (size_t i = 0; i < 4; ++i) uv.push_back((positions[3 * i + 2] + 1) / 2), uv.push_back((1 - positions[3 * i]) / 2);
  const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
  std::string bin;
  for (const std::vector<float>* a : std::array<const std::vector<float>*, 4>{&positions, &normals, &tangents, &uv})
    bin.append(reinterpret_cast<const char*>(a->data()), a->size() * 4);
  bin.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 2);
  const std::string dir = test::tempDir();
  test::writeText(dir + "/quad.bin", bin);
  test::writeText(dir + "/quad.gltf", fmt::format(R"({{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}], "materials": [{{"name": "m"}}],
  "meshes": [{{"name": "quad", "primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3}},
                                              "indices": 4, "material": 0}}]}}],
  "buffers": [{{"uri": "quad.bin", "byteLength": {}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 48}},
                  {{"buffer": 0, "byteOffset": 96, "byteLength": 64}}, {{"buffer": 0, "byteOffset": 160, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": 192, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}},
                {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
                {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC4"}},
                {{"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"}},
                {{"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}})",
                                                  bin.size()));
  return dir + "/quad.gltf";
}

/// The shading normal of @p desc's first shape at the centroid of each of its faces, with the normal map
/// @p texel given to its material (faces traced as they are: patch f is face f).
std::vector<Vec3> mappedNormals(SceneDesc desc, const Vec3& texel) {
  const ShapeDesc& s = desc.shapes.at(0);
  desc.materials.at(size_t(s.material)).normalTexture = constantNormalMap(texel);
  const RenderScene scene(desc);
  std::vector<Vec3> out;
  for (size_t f = 0; f < s.faces.size(); ++f) {
    Vec3d c(0.0);
    for (int k = 0; k < s.faces[f].count; ++k) c += s.vertices[s.faces[f].v[k]] / double(s.faces[f].count);
    Hit h;
    h.p = Vec3(c), h.ng = Vec3(0, 1, 0), h.patch = uint32_t(f);
    out.push_back(scene.shadingNormal(h));
  }
  return out;
}

TEST(GltfTangents, NormalMapTiltsInTheFilesTangentFrame) {
  // A texel tilted 40° towards +x tilts the normal towards the file's tangent +x (the generated frame's ∂p/∂u is
  // +z), one towards +y towards its bitangent w·N×T = (0, 0, −w) (the generated frame's image up is +x).
  const float c = std::cos(glm::radians(40.0f)), s = std::sin(glm::radians(40.0f));
  for (const float w : {1.0f, -1.0f}) {
    const SceneDesc desc = loadScene(writeTangentQuad(w));
    ASSERT_EQ(desc.shapes.size(), 1u);
    const ShapeDesc& shape = desc.shapes[0];
    ASSERT_TRUE(shape.hasTangents());
    ASSERT_EQ(shape.tangents.size(), 4 * shape.faces.size());
    for (size_t f = 0; f < shape.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        test::expectNear(shape.tangents[4 * f + size_t(k)], Vec3(1, 0, 0), 1e-6f, "tangent");
        test::expectNear(shape.bitangents[4 * f + size_t(k)], Vec3(0, 0, -w), 1e-6f, "bitangent");
      }
    for (const Vec3& n : mappedNormals(desc, tilted(40, false))) test::expectNear(n, Vec3(s, c, 0), 2e-3f, fmt::format("+x, w {}", w));
    for (const Vec3& n : mappedNormals(desc, tilted(40, true))) test::expectNear(n, Vec3(0, c, -w * s), 2e-3f, fmt::format("+y, w {}", w));
  }
}

TEST(GltfTangents, MirroredMeshShapeKeepsTheFilesFrame) {
  // The same quad as a JSON mesh shape mirrored in x: the tangent becomes −x (a surface vector, by the matrix), the
  // bitangent stays (0, 0, −1), the winding is reversed and the front stays +y.
  const float c = std::cos(glm::radians(40.0f)), s = std::sin(glm::radians(40.0f));
  const std::string gltf = writeTangentQuad(1.0f);
  const SceneDesc desc = test::sceneFromJson(fmt::format(R"({{
    "camera": {{"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30, "resolution": [8, 8]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": 0.8}}}},
    "shapes": [{{"type": "mesh", "material": "floor", "file": "{}", "transform": {{"scale": [-1, 1, 1]}}}}],
    "lights": [{{"type": "directional", "direction": [0, -1, 0], "irradiance": 1}}]}})", gltf));
  ASSERT_TRUE(desc.shapes.at(0).hasTangents());
  for (const Vec3& n : mappedNormals(desc, tilted(40, false))) test::expectNear(n, Vec3(-s, c, 0), 2e-3f, "+x");
  for (const Vec3& n : mappedNormals(desc, tilted(40, true))) test::expectNear(n, Vec3(0, c, -s), 2e-3f, "+y");
}

TEST(GltfTangents, TangentsChangeTheSceneHashOnlyUnderANormalMap) {
  SceneDesc desc = loadScene(writeTangentQuad(1.0f));
  SceneDesc without = desc;
  without.shapes[0].tangents.clear(), without.shapes[0].bitangents.clear();
  EXPECT_EQ(hashScene(desc), hashScene(without));  // nothing reads them
  desc.materials[size_t(desc.shapes[0].material)].normalTexture = constantNormalMap(tilted(40, false));
  without.materials[size_t(without.shapes[0].material)].normalTexture = constantNormalMap(tilted(40, false));
  EXPECT_NE(hashScene(desc), hashScene(without));
}

/// Writes @p dir/quad.obj, a 2 × 2 quad at y = 0 with texture coordinates over [0,1]², and its
/// quad.mtl: material "m" of Kd 0.5 and the lines @p mtl. @return the .obj's path.
std::string writeQuadObj(const std::string& dir, const std::string& mtl) {
  test::writeText(dir + "/quad.mtl", "newmtl m\nKd 0.5 0.5 0.5\n" + mtl);
  test::writeText(dir + "/quad.obj",
                  "mtllib quad.mtl\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
                  "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n");
  return dir + "/quad.obj";
}

/// Writes, in a fresh directory, the quad of writeTangentQuad as an OBJ (vt giving the same u, v) whose material
/// "m" has `norm n.png` (a 1 × 1 PNG of @p rgb) and whose MTL adds @p extra lines (bump maps, a second material).
/// @return the .obj's path.
std::string writeNormObj(const std::array<uint8_t, 3>& rgb, const std::string& extra) {
  const std::string dir = test::tempDir();
  image::writePng(dir + "/n.png", 1, 1, rgb.data());
  return writeQuadObj(dir, "norm n.png\n" + extra);
}

TEST(ObjNormalMaps, NormIsTheMaterialsNormalMap) {
  // norm's texel t (linear) tilts the normal to normalize((2t − 1) in the generated frame T = +z, B = +x, N = +y).
  const std::array<uint8_t, 3> rgb = {210, 128, 225};
  SceneDesc desc = loadScene(writeNormObj(rgb, ""));
  const MaterialDesc& m = desc.materials.at(size_t(desc.shapes.at(0).material));
  ASSERT_TRUE(m.normalTexture);
  const Color texel = m.normalTexture->lookup(Vec2(0.3f, 0.6f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(texel[c], rgb[size_t(c)] / 255.0f, 1e-6f) << "not sRGB-decoded";
  const Vec3 t = 2.0f * texel - Vec3(1.0f);
  const Vec3 expected = glm::normalize(Vec3(t.y, t.z, t.x));
  const ShapeDesc& s = desc.shapes[0];
  const RenderScene scene(desc);
  for (size_t f = 0; f < s.faces.size(); ++f) {
    Vec3d c(0.0);
    for (int k = 0; k < s.faces[f].count; ++k) c += s.vertices[s.faces[f].v[k]] / double(s.faces[f].count);
    Hit h;
    h.p = Vec3(c), h.ng = Vec3(0, 1, 0), h.patch = uint32_t(f);
    test::expectNear(scene.shadingNormal(h), expected, 1e-4f, fmt::format("face {}", f));
  }
}

/// Writes the quad of writeNormObj with an MTL of @p mtl (material "m") and an 8 × 8 grey PNG h.png whose value is
/// 16·x (a ramp along u) or 16·y (along v), read linear: h = 16·k/255 per texel. @return the .obj's path.
std::string writeBumpObj(const std::string& mtl, bool alongV) {
  const std::string dir = test::tempDir();
  std::vector<uint8_t> grey;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) grey.insert(grey.end(), 3, uint8_t(16 * (alongV ? y : x)));
  image::writePng(dir + "/h.png", 8, 8, grey.data());
  return writeQuadObj(dir, mtl);
}

/// The shading normal at the quad's centre (uv (½, ½)) of the OBJ at @p obj.
Vec3 centreShadingNormal(const std::string& obj, std::string* err = nullptr) {
  testing::internal::CaptureStderr();
  const SceneDesc desc = loadScene(obj);
  if (err) *err = testing::internal::GetCapturedStderr();
  else testing::internal::GetCapturedStderr();
  const RenderScene scene(desc);
  Hit h;
  h.p = Vec3(0.0f), h.ng = Vec3(0, 1, 0), h.patch = 0;
  return scene.shadingNormal(h);
}

TEST(ObjNormalMaps, BumpHeightMapsBecomeNormalMaps) {
  // A height ramp of 16/255 per texel tilts the normal by atan(16/255) away from where the surface rises
  // (common/materials/bump_map.h), in the generated frame T = +z (u), B = +x (v), N = +y; one stderr line counts them.
  const float step = 16.0f / 255.0f;
  std::string err;
  const Vec3 alongU = centreShadingNormal(writeBumpObj("bump h.png\n", false), &err);
  test::expectNear(alongU, glm::normalize(Vec3(0.0f, 1.0f, -step)), 1e-4f, "ramp along u");
  EXPECT_NE(err.find("quad.obj: 1 bump (height) map turned into normal maps"), std::string::npos) << err;
  const Vec3 alongV = centreShadingNormal(writeBumpObj("map_bump h.png\n", true));
  test::expectNear(alongV, glm::normalize(Vec3(-step, 1.0f, 0.0f)), 1e-4f, "ramp along v");
}

TEST(ObjNormalMaps, BumpSlotHoldingANormalMapIsUsedAsIt) {
  // Blender's OBJ exporter writes normal maps as map_Bump: a bluish image is taken as the normal map it is.
  const std::array<uint8_t, 3> rgb = {150, 128, 240};
  const std::string obj = writeNormObj(rgb, "");
  test::writeText(obj.substr(0, obj.size() - 3) + "mtl", "newmtl m\nKd 0.5 0.5 0.5\nmap_Bump -bm 1.0 n.png\n");
  const Vec3 t = 2.0f * Vec3(rgb[0], rgb[1], rgb[2]) / 255.0f - Vec3(1.0f);
  test::expectNear(centreShadingNormal(obj), glm::normalize(Vec3(t.y, t.z, t.x)), 1e-4f, "map_Bump normal map");
}

}  // namespace
