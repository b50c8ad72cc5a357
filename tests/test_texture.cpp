// Textures: bilinear lookups of known values, wrap modes, KHR_texture_transform, decoding through
// OpenImageIO (8-bit sRGB PNG, 16-bit PPM, float EXR), texture coordinates on quads, subdivided and adaptive
// patches (render/scene/surface_textures.h), and a missing texture named with its material.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "render/output/image_io.h"
#include "render/scene/surface_textures.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

using ::testing::HasSubstr;

/// The linear value of the sRGB code @p c ∈ [0, 1], computed here independently.
double srgb(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

/// A 2 × 2 texture: red, green (top row), blue, white (bottom row).
Texture checker2x2() {
  Texture t;
  t.image = std::make_shared<const TexelImage>(
      makeTexelImage(2, 2, {Color(1, 0, 0), Color(0, 1, 0), Color(0, 0, 1), Color(1, 1, 1)}, "checker"));
  return t;
}

void expectColor(const Color& c, const Color& expected, double tolerance, const std::string& what = "") {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], expected[i], tolerance) << what << " channel " << i;
}

TEST(Texture, BilinearIsExactAtTexelCentresAndLinearBetween) {
  const Texture t = checker2x2();
  expectColor(t.lookup(Vec2(0.25f, 0.25f)), Color(1, 0, 0), 1e-6, "top left");
  expectColor(t.lookup(Vec2(0.75f, 0.25f)), Color(0, 1, 0), 1e-6, "top right");
  expectColor(t.lookup(Vec2(0.25f, 0.75f)), Color(0, 0, 1), 1e-6, "bottom left");
  expectColor(t.lookup(Vec2(0.75f, 0.75f)), Color(1, 1, 1), 1e-6, "bottom right");
  expectColor(t.lookup(Vec2(0.5f, 0.25f)), Color(0.5f, 0.5f, 0), 1e-6, "between the top two");
  expectColor(t.lookup(Vec2(0.5f, 0.5f)), Color(0.5f, 0.5f, 0.5f), 1e-6, "the middle");
  EXPECT_EQ(t.image->mean, Color(0.5f, 0.5f, 0.5f));
}

TEST(Texture, WrapModes) {
  Texture t = checker2x2();
  // Repeat: one period away is the same; the edge blends with the opposite side.
  expectColor(t.lookup(Vec2(1.25f, -0.75f)), Color(1, 0, 0), 1e-5, "repeat");
  expectColor(t.lookup(Vec2(0.0f, 0.25f)), Color(0.5f, 0.5f, 0), 1e-6, "repeat, left edge");
  t.wrapU = t.wrapV = TextureWrap::ClampToEdge;
  expectColor(t.lookup(Vec2(0.0f, 0.25f)), Color(1, 0, 0), 1e-6, "clamp, left edge");
  expectColor(t.lookup(Vec2(-3.0f, 7.0f)), Color(0, 0, 1), 1e-6, "clamp, far outside");
  t.wrapU = t.wrapV = TextureWrap::MirroredRepeat;
  expectColor(t.lookup(Vec2(1.25f, 0.25f)), Color(0, 1, 0), 1e-5, "mirror: u = 1.25 reads u = 0.75");
  expectColor(t.lookup(Vec2(-0.25f, 0.25f)), Color(1, 0, 0), 1e-5, "mirror: u = -0.25 reads u = 0.25");
  expectColor(t.lookup(Vec2(1.0f, 0.25f)), Color(0, 1, 0), 1e-6, "mirror: the edge is the edge texel");
}

TEST(Texture, KhrTextureTransform) {
  TextureTransform tr;
  tr.offset = Vec2(0.5f, 0.25f);
  tr.scale = Vec2(2.0f, 3.0f);
  const Vec2 a = tr.apply(Vec2(0.1f, 0.2f));
  EXPECT_NEAR(a.x, 0.7, 1e-6);
  EXPECT_NEAR(a.y, 0.85, 1e-6);
  tr = TextureTransform();
  tr.rotation = float(kPi / 2);  // glTF: [cos sin; -sin cos]·uv, so (1, 0) goes to (0, -1)
  const Vec2 b = tr.apply(Vec2(1.0f, 0.0f));
  EXPECT_NEAR(b.x, 0.0, 1e-6);
  EXPECT_NEAR(b.y, -1.0, 1e-6);
  Texture t = checker2x2();
  t.transform.offset = Vec2(0.5f, 0.0f);  // shifts the image by one texel
  expectColor(t.lookup(Vec2(0.25f, 0.25f)), Color(0, 1, 0), 1e-6, "offset");
}

TEST(Texture, DecodesSrgbPngSixteenBitAndFloat) {
  const std::string dir = test::tempDir();
  const uint8_t rgb[12] = {0, 64, 128, 255, 255, 255, 10, 20, 30, 200, 100, 50};
  image::writePng(dir + "/t.png", 2, 2, rgb);
  const TexelImage png = readTexelImage(dir + "/t.png", true);
  ASSERT_EQ(png.width, 2);
  ASSERT_EQ(png.height, 2);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(png.at((i / 3) % 2, i / 6)[i % 3], srgb(rgb[i] / 255.0), 1e-6) << i;
  EXPECT_NEAR(readTexelImage(dir + "/t.png", false).at(0, 0)[1], 64 / 255.0, 1e-6);  // data, not colour

  std::string ppm = "P6\n1 1\n65535\n";  // 16 bits, big-endian
  for (uint16_t v : {uint16_t(0), uint16_t(32768), uint16_t(65535)}) ppm += char(v >> 8), ppm += char(v & 0xff);
  test::writeText(dir + "/t.ppm", ppm);
  // Within 1e-4: 8 bits would be 1.6e-3 off in G.
  expectColor(readTexelImage(dir + "/t.ppm", true).at(0, 0), Color(0.0f, float(srgb(32768 / 65535.0)), 1.0f), 1e-4);

  const float hdr[3] = {2.5f, 0.25f, 0.0f};
  image::writeExr(dir + "/t.exr", 1, 1, {"R", "G", "B"}, hdr);
  expectColor(readTexelImage(dir + "/t.exr", true).at(0, 0), Color(2.5f, 0.25f, 0.0f), 0);  // float: linear as stored

  EXPECT_THROW(readTexelImage(dir + "/none.png", true), InputError);
  test::writeText(dir + "/bad.png", "not an image");
  EXPECT_THROW(readTexelImage(dir + "/bad.png", true), InputError);
}

/// A scene of one textured quad (its natural coordinates: v[0] at (0, 1), v[2] at (1, 0)).
SceneDesc texturedQuad(double patchSize = 0.5) {
  SceneDesc s = test::sceneFromJson(fmt::format(R"({{
    "materials": {{"floor": {{"type": "diffuse", "albedo": 0.5}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[0,0,0],[2,0,0],[2,0,-1],[0,0,-1]]}}],
    "lights": [{{"type": "point", "position": [1, 1, -0.5], "power": 10}}],
    "settings": {{"patch_size": {}}}}})", patchSize));
  s.materials[0].albedoTexture = std::make_shared<const Texture>(checker2x2());
  return s;
}

/// The quad's natural coordinates of a point on it: u along x (0..2 m), v from z = −1 (0) to z = 0 (1).
Vec2 expectedUv(const Vec3& p) { return Vec2(p.x / 2.0f, 1.0f + p.z); }

/// Checks uvAt and albedoAt at points spread over every patch of @p mesh.
void expectUvOnPatches(const SceneDesc& s, const PatchMesh& mesh) {
  const SurfaceTextures textures(s, mesh);
  ASSERT_FALSE(textures.empty());
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    ASSERT_TRUE(textures.textured(j));
    for (const Vec3& x : {p.centroid, 0.5f * (p.centroid + p.v[0]), 0.5f * (p.centroid + p.v[p.count - 1])}) {
      const Vec2 uv = textures.uvAt(j, x), e = expectedUv(x);
      EXPECT_NEAR(uv.x, e.x, 1e-5) << "patch " << j;
      EXPECT_NEAR(uv.y, e.y, 1e-5) << "patch " << j;
      expectColor(textures.albedoAt(j, x), 0.5f * s.materials[0].albedoTexture->lookup(e), 1e-5);
    }
  }
}

TEST(Texture, UvOnAQuadItsSubdivisionAndAnAdaptiveMesh) {
  const SceneDesc s = texturedQuad();
  expectUvOnPatches(s, buildPatches(s, kFacesAsTheyAre));
  expectUvOnPatches(s, buildPatches(s, 0.3));
  // An adaptive mesh: patches of several sizes, not in face order.
  PatchMesh adaptive;
  std::vector<std::vector<Vec3d>> pieces;
  const Vec3d left[4] = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}}, right[4] = {{1, 0, 0}, {2, 0, 0}, {2, 0, -1}, {1, 0, -1}};
  subdividePolygon(right, 4, 0.2, pieces);
  subdividePolygon(left, 4, 0.7, pieces);
  for (const auto& piece : pieces) {
    Patch p;
    p.count = uint32_t(piece.size());
    for (uint32_t k = 0; k < p.count; ++k) p.v[k] = Vec3(piece[k]);
    computePatchGeometry(p);
    adaptive.patches.push_back(p);
  }
  expectUvOnPatches(s, adaptive);
}

TEST(Texture, UvFollowsAMeshsTrianglesAndCornerCoordinates) {
  // Two triangles of the quad, the second with its own (seam) coordinates for a shared corner.
  SceneDesc s = texturedQuad();
  ShapeDesc& shape = s.shapes[0];
  shape.faces = {Face{{0, 1, 2, 0}, 3}, Face{{0, 2, 3, 0}, 3}};
  shape.uv = {Vec2(0, 1), Vec2(1, 1), Vec2(1, 0), Vec2(0), Vec2(0, 1), Vec2(3, 0), Vec2(0, 0), Vec2(0)};
  const PatchMesh mesh = buildPatches(s, kFacesAsTheyAre);
  const SurfaceTextures textures(s, mesh);
  ASSERT_EQ(mesh.size(), 2u);
  const Vec2 a = textures.uvAt(0, Vec3(1.5f, 0, -0.25f)), b = textures.uvAt(1, Vec3(0.5f, 0, -0.75f));
  EXPECT_NEAR(a.x, 0.75, 1e-6);
  EXPECT_NEAR(a.y, 0.75, 1e-6);
  EXPECT_NEAR(b.x, 0.75, 1e-6);  // corner 2 has u = 3 in this face
  EXPECT_NEAR(b.y, 0.25, 1e-6);
}

TEST(Texture, PatchAverageIsTheMeanOverThePatch) {
  const SceneDesc s = texturedQuad();
  const PatchMesh mesh = buildPatches(s, kFacesAsTheyAre);  // one patch over the whole image
  const SurfaceTextures textures(s, mesh);
  expectColor(textures.patchAlbedo(0), Color(0.25f), 2e-2);  // 0.5 × the image mean (8 × 8 points, bilinear)
}

// Each missing-texture case (here and below) writes its own scene and checks its own message: data, not logic.
TEST(Texture, MissingTextureNamesFileAndMaterial) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/scene.json", R"({"materials": {"wood": {"type": "diffuse", "albedo_texture": "wood.png"}},
    "shapes": [{"type": "quad", "material": "wood", "vertices": [[0,0,0],[1,0,0],[1,0,-1],[0,0,-1]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}]})");
  try {
    loadScene(dir + "/scene.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("wood.png"));
    EXPECT_THAT(e.what(), HasSubstr("material \"wood\""));
  }
#ifdef FIRSTSHOT_RENDER_EXE
  const test::CommandResult r = test::run(std::string(FIRSTSHOT_RENDER_EXE) + " " + dir + "/scene.json -o " + dir + "/x.exr");
  EXPECT_EQ(r.exitCode, kExitBadInput);
  EXPECT_THAT(r.output, HasSubstr("wood.png"));
#endif
}

TEST(Texture, JsonKeysAndQuadCoordinates) {
  const std::string dir = test::tempDir();
  const uint8_t rgb[3] = {255, 128, 0};
  image::writePng(dir + "/t.png", 1, 1, rgb);
  test::writeText(dir + "/scene.json", R"({"materials": {"m": {"type": "glossy", "specular": 0.1, "exponent": 10,
      "albedo": 0.5, "albedo_texture": {"file": "t.png", "wrap": "clamp", "offset": [0.5, 0], "scale": [2, 2], "rotation": 90}}},
    "shapes": [{"type": "box", "material": "m", "min": [0, 0, 0], "max": [1, 1, 1]}],
    "lights": [{"type": "point", "position": [0, 3, 0], "power": 1}]})");
  const SceneDesc s = loadScene(dir + "/scene.json");
  const Texture& t = *s.materials[0].albedoTexture;
  EXPECT_EQ(t.wrapU, TextureWrap::ClampToEdge);
  EXPECT_NEAR(t.transform.rotation, kPi / 2, 1e-6);
  EXPECT_EQ(t.transform.scale, Vec2(2.0f));
  expectColor(s.materials[0].albedo, Color(0.5f), 0);
  EXPECT_EQ(s.shapes[0].uv.size(), 4 * s.shapes[0].faces.size());
  EXPECT_NE(hashScene(s), [&] {
    SceneDesc plain = s;
    plain.materials[0].albedoTexture = nullptr;
    return hashScene(plain);
  }());
}

TEST(Texture, PbrBaseColourTextureKey) {
  const std::string dir = test::tempDir();
  const uint8_t rgb[3] = {255, 128, 0};
  image::writePng(dir + "/t.png", 1, 1, rgb);
  test::writeText(dir + "/scene.json", R"({"materials": {"m": {"type": "pbr", "base_color": [0.5, 0.5, 1],
      "metallic": 0, "roughness": 0.5, "base_color_texture": {"file": "t.png", "wrap": "mirror"}}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,0,-1],[0,0,-1]]}],
    "lights": [{"type": "point", "position": [0, 3, 0], "power": 1}]})");
  const SceneDesc s = loadScene(dir + "/scene.json");
  const MaterialDesc& m = s.materials[0];
  EXPECT_EQ(m.type, MaterialType::Pbr);
  ASSERT_NE(m.albedoTexture, nullptr);
  EXPECT_EQ(m.albedoTexture->wrapU, TextureWrap::MirroredRepeat);
  expectColor(m.albedo, Color(0.5f, 0.5f, 1.0f), 0);  // the factor, not reset by the texture
  // "albedo_texture" is the diffuse and glossy key, not pbr's.
  test::writeText(dir + "/bad.json", R"({"materials": {"m": {"type": "pbr", "albedo_texture": "t.png"}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,0,-1],[0,0,-1]]}]})");
  EXPECT_THROW(loadScene(dir + "/bad.json"), InputError);
}

TEST(Texture, PbrMetallicRoughnessTextureKey) {
  // Read as stored (not sRGB-decoded): G 128 is roughness × 128/255, B 255 metallic × 1; the same file as a base
  // colour is decoded (one image per use); hashed; a missing file names the file, the key and the material.
  const std::string dir = test::tempDir();
  const uint8_t rgb[3] = {0, 128, 255};
  image::writePng(dir + "/mr.png", 1, 1, rgb);
  test::writeText(dir + "/scene.json", R"({"materials": {"m": {"type": "pbr", "roughness": 0.5,
      "base_color_texture": "mr.png", "metallic_roughness_texture": "mr.png"}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,0,-1],[0,0,-1]]}],
    "lights": [{"type": "point", "position": [0, 3, 0], "power": 1}]})");
  const SceneDesc s = loadScene(dir + "/scene.json");
  const MaterialDesc& m = s.materials[0];
  ASSERT_NE(m.metallicRoughnessTexture, nullptr);
  EXPECT_NEAR(m.metallicRoughnessTexture->image->mean.y, 128 / 255.0, 1e-6);
  EXPECT_NEAR(m.metallicRoughnessTexture->image->mean.z, 1.0, 1e-6);
  EXPECT_NEAR(m.albedoTexture->image->mean.y, 0.2158605, 1e-4);  // sRGB 128
  EXPECT_EQ(m.roughness, 0.5f);
  EXPECT_NE(hashScene(s), [&] {
    SceneDesc plain = s;
    plain.materials[0].metallicRoughnessTexture = nullptr;
    return hashScene(plain);
  }());
  test::writeText(dir + "/missing.json", R"({"materials": {"steel": {"type": "pbr", "metallic_roughness_texture": "no.png"}},
    "shapes": [{"type": "quad", "material": "steel", "vertices": [[0,0,0],[1,0,0],[1,0,-1],[0,0,-1]]}],
    "lights": [{"type": "point", "position": [0, 3, 0], "power": 1}]})");
  try {
    loadScene(dir + "/missing.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no.png"));
    EXPECT_THAT(e.what(), HasSubstr("metallic_roughness_texture"));
    EXPECT_THAT(e.what(), HasSubstr("material \"steel\""));
  }
}

}  // namespace
}  // namespace firstshot
