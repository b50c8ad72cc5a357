// glTF textures folded into material factors (common/formats/assets/gltf_materials.h, common/materials/texture_image.h): a quad with
// texture coordinates, its .bin buffer and PNG (libpng) / JPEG (libjpeg) images written here.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>
// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
#include <jpeglib.h>

#include "common/formats/assets/mesh_import.h"
#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/materials/texture_image.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

using ::testing::HasSubstr;

/// The linear value of the 8-bit sRGB code @p v (IEC 61966-2-1), computed here independently.
double srgb(int v) {
  const double c = v / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// A PNG of @p width x @p height RGB texels (rows from the top, 3 bytes each), encoded by libpng.
std::string pngBytes(int width, int height, const std::vector<uint8_t>& rgb) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(width), image.height = png_uint_32(height);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  EXPECT_TRUE(png_image_write_get_memory_size(image, size, 0, rgb.data(), 0, nullptr));
  std::string bytes(size, '\0');
  EXPECT_TRUE(png_image_write_to_memory(&image, bytes.data(), &size, 0, rgb.data(), 0, nullptr)) << image.message;
  bytes.resize(size);
  return bytes;
}

/// A 2 x 2 PNG: the top row @p top, the bottom row @p bottom (grey levels).
std::string png2x2(uint8_t top, uint8_t bottom) {
  return pngBytes(2, 2, {top, top, top, top, top, top, bottom, bottom, bottom, bottom, bottom, bottom});
}

/// An 8 x 8 grey JPEG of level @p level (quality 95), encoded by libjpeg.
std::string jpegGrey(uint8_t level) {
  jpeg_compress_struct info;
  jpeg_error_mgr error;
  info.err = jpeg_std_error(&error);
  jpeg_create_compress(&info);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&info, &out, &size);
  info.image_width = 8, info.image_height = 8, info.input_components = 3, info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, 95, TRUE);
  jpeg_start_compress(&info, TRUE);
  std::vector<uint8_t> row(8 * 3, level);
  while (info.next_scanline < 8) {
    JSAMPROW p = row.data();
    jpeg_write_scanlines(&info, &p, 1);
  }
  jpeg_finish_compress(&info);
  std::string bytes(reinterpret_cast<const char*>(out), size);
  jpeg_destroy_compress(&info);
  std::free(out);
  return bytes;
}

/// The unit quad in the z = 0 plane, facing +z, as two triangles whose texture coordinates cover
/// [u0, u1] x [v0, v1] (v down from the image's top: the vertex at y = 1 has v0).
std::string quadBuffer(float u0, float u1, float v0, float v1) {
  const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const float uvs[8] = {u0, v1, u1, v1, u1, v0, u0, v0};
  const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::string bytes(reinterpret_cast<const char*>(positions), sizeof positions);
  bytes.append(reinterpret_cast<const char*>(uvs), sizeof uvs);
  bytes.append(reinterpret_cast<const char*>(indices), sizeof indices);
  return bytes;  // 92 bytes
}

/// Writes quad.gltf in a fresh directory: the quad of quadBuffer(uv) in quad.bin, its material @p material (JSON),
/// and its image: "tex.png" beside it or, with @p embedded, the PNG bytes after the geometry in quad.bin.
/// @return the .gltf's path.
std::string writeQuad(const std::string& material, const std::string& image, std::array<float, 4> uv = {0, 1, 0, 1},
                      bool embedded = false) {
  const std::string dir = test::tempDir();
  std::string bin = quadBuffer(uv[0], uv[1], uv[2], uv[3]);
  std::string imageJson = R"({"uri": "tex.png"})";
  if (embedded) {
    imageJson = R"({"bufferView": 3, "mimeType": "image/png"})";
    bin += image;
  } else {
    test::writeText(dir + "/tex.png", image);
  }
  test::writeText(dir + "/quad.bin", bin);
  const std::string b = std::to_string(bin.size()), n = std::to_string(image.size());
  test::writeText(dir + "/quad.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}],
  "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
  "materials": [)" + material + R"(],
  "textures": [{"source": 0}, {"source": 1}],
  "images": [)" + imageJson + R"(, {"uri": "missing.png"}],
  "buffers": [{"uri": "quad.bin", "byteLength": )" + b + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 80, "byteLength": 12}, {"buffer": 0, "byteOffset": 92, "byteLength": )" + n + R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})");
  return dir + "/quad.gltf";
}

const char* kEmissive = R"({"name": "screen", "emissiveFactor": [2, 3, 4], "emissiveTexture": {"index": 0}})";

/// The material of the quad of the scene at @p path.
MaterialDesc quadMaterial(const std::string& path) {
  const SceneDesc s = loadScene(path);
  EXPECT_EQ(s.shapes.size(), 1u);
  return s.materials.at(s.shapes.at(0).material);
}

void expectColor(const Color& c, const Color& expected, double tolerance) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], expected[i], tolerance) << "channel " << i;
}

TEST(GltfTextures, BlackEmissiveTextureEmitsNothing) {
  const SceneDesc s = loadScene(writeQuad(kEmissive, png2x2(0, 0)));
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_FALSE(s.materials.at(s.shapes[0].material).isEmissive());
  EXPECT_TRUE(s.lights.empty()) << "no area light";
}

TEST(GltfTextures, HalfWhiteEmissiveTextureEmitsFactorTimesMean) {
  for (const bool embedded : {false, true}) {
    SCOPED_TRACE(embedded ? "image in the buffer" : "image file");
    const SceneDesc s = loadScene(writeQuad(kEmissive, png2x2(255, 0), {0, 1, 0, 1}, embedded));
    const MaterialDesc& m = s.materials.at(s.shapes.at(0).material);
    expectColor(m.emission, Color(2, 3, 4) * 0.5f, 1e-6);  // mean of 1, 1, 0, 0 (sRGB 255 -> 1, 0 -> 0)
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Area);
  }
}

TEST(GltfTextures, EmissionIsTheMeanOverTheMeshsTexels) {
  // The quad's coordinates cover only the bottom row (v in [0.5, 1]): black, so it emits nothing, although
  // half the texture is white. Covering only the top row: factor x 1. (A flipped v would swap the two.)
  EXPECT_FALSE(quadMaterial(writeQuad(kEmissive, png2x2(255, 0), {0, 1, 0.5f, 1})).isEmissive());
  expectColor(quadMaterial(writeQuad(kEmissive, png2x2(255, 0), {0, 1, 0, 0.5f})).emission, Color(2, 3, 4), 1e-6);
  // A grey texture: sRGB decoded.
  expectColor(quadMaterial(writeQuad(kEmissive, png2x2(128, 128))).emission, Color(2, 3, 4) * float(srgb(128)), 1e-6);
}

TEST(GltfTextures, JpegEmissiveTexture) {
  // JPEG is lossy: a flat 8 x 8 block decodes to within a level or two of its value.
  const Color e = quadMaterial(writeQuad(kEmissive, jpegGrey(200))).emission;
  expectColor(e, Color(2, 3, 4) * float(srgb(200)), 4 * 2 * (srgb(202) - srgb(200)));
  EXPECT_GT(e.x, 0.0f);
}

TEST(GltfTextures, MetallicRoughnessDefaultsAndTexturesMultiply) {
  // No factors: the glTF 2.0 defaults (base colour 1, metallic 1, roughness 1), times the textures at each point:
  // base colour x the base-colour texture (sRGB), metallic x its B, roughness x its G (linear).
  const std::string rgbPng = pngBytes(1, 1, {128, 128, 128});
  const SceneDesc plain = loadScene(writeQuad(R"({"name": "metal"})", rgbPng));
  const MaterialDesc& metal = plain.materials.at(plain.shapes.at(0).material);
  EXPECT_EQ(metal.type, MaterialType::Pbr);  // a white rough metal
  expectColor(metal.albedo, Color(1.0f), 1e-7);
  EXPECT_EQ(metal.metallic, 1.0f);
  EXPECT_EQ(metal.roughness, 1.0f);

  const std::string dir = std::filesystem::path(writeQuad(R"({"name": "textured",
      "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 2}}})",
                                                             pngBytes(1, 1, {128, 128, 128}))).parent_path();
  std::string gltf = test::readFile(dir + "/quad.gltf");
  gltf.replace(gltf.find(R"({"source": 1}])"), 14, R"({"source": 1}, {"source": 2}])");
  gltf.replace(gltf.find(R"({"uri": "missing.png"}])"), 23, R"({"uri": "missing.png"}, {"uri": "mr.png"}])");
  test::writeText(dir + "/quad.gltf", gltf);
  test::writeText(dir + "/mr.png", pngBytes(2, 1, {0, 100, 40, 0, 156, 88}));  // G mean 128, B mean 64 (linear)
  const MaterialDesc m = quadMaterial(dir + "/quad.gltf");
  const double base = srgb(128), metallic = 64 / 255.0, roughness = 128 / 255.0;
  EXPECT_EQ(m.type, MaterialType::Pbr);
  // The base-colour texture stays a texture (read through TEXCOORD_0): the albedo is the factor (1 here), which
  // the texture multiplies at each point; on average as the mean folded in.
  ASSERT_NE(m.albedoTexture, nullptr);
  expectColor(m.albedo, Color(1.0f), 1e-6);
  expectColor(m.albedo * m.albedoTexture->image->mean, Color(float(base)), 1e-6);
  // So does the metallic-roughness texture (not sRGB-decoded): the factors (1 here) times its B and G per point.
  ASSERT_NE(m.metallicRoughnessTexture, nullptr);
  EXPECT_EQ(m.metallic, 1.0f);
  EXPECT_EQ(m.roughness, 1.0f);
  EXPECT_NEAR(m.metallicRoughnessTexture->image->mean.z, metallic, 1e-6);
  EXPECT_NEAR(m.metallicRoughnessTexture->image->mean.y, roughness, 1e-6);
  EXPECT_NEAR(m.metallicRoughnessTexture->lookup(Vec2(0.25f, 0.5f)).y, 100 / 255.0, 1e-6);  // texel 0, not sRGB
}

TEST(GltfTextures, TextureCoordinatesReachTheShape) {
  // glTF's TEXCOORD_0 as it is (v down); the quad's first triangle is vertices 0, 1, 2 at v = 1, 1, 0.
  const SceneDesc s = loadScene(writeQuad(R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
      "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2]}}}, "metallicFactor": 0}})",
                                          png2x2(255, 0)));
  const ShapeDesc& shape = s.shapes.at(0);
  ASSERT_EQ(shape.uv.size(), 4 * shape.faces.size());
  for (size_t f = 0; f < shape.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3d& p = shape.vertices[shape.faces[f].v[k]];
      EXPECT_NEAR(shape.cornerUv(f, k).x, p.x, 1e-6);
      EXPECT_NEAR(shape.cornerUv(f, k).y, 1 - p.y, 1e-6);
    }
  const MaterialDesc& m = s.materials.at(shape.material);
  ASSERT_NE(m.albedoTexture, nullptr);
  EXPECT_EQ(m.albedoTexture->transform.offset, Vec2(0.5f, 0.0f));
  EXPECT_EQ(m.albedoTexture->transform.scale, Vec2(2.0f));
}

TEST(GltfTextures, ObjTextureCoordinatesAreFlippedAndMapKdIsTheAlbedoTexture) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/tex.png", png2x2(255, 0));
  test::writeText(dir + "/m.mtl", "newmtl wood\nKd 0.5 0.5 0.5\nmap_Kd tex.png\nnewmtl lost\nKd 1 1 1\nmap_Kd none.png\n");
  test::writeText(dir + "/t.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                  "usemtl wood\nf 1/1 2/2 3/3\nv 0 0 1\nv 1 0 1\nv 1 1 1\nusemtl lost\nf 4/1 5/2 6/3\n");
  testing::internal::CaptureStderr();
  const SceneDesc s = loadScene(dir + "/t.obj");
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(s.shapes.size(), 2u);
  const ShapeDesc& shape = s.shapes[0];
  ASSERT_EQ(shape.uv.size(), 4u);
  EXPECT_EQ(shape.cornerUv(0, 0), Vec2(0, 1));  // vt (0, 0): the image's bottom left
  EXPECT_EQ(shape.cornerUv(0, 1), Vec2(1, 1));
  EXPECT_EQ(shape.cornerUv(0, 2), Vec2(1, 0));
  const MaterialDesc& wood = s.materials.at(shape.material);
  ASSERT_NE(wood.albedoTexture, nullptr);
  expectColor(wood.albedo, Color(0.5f), 1e-7);
  EXPECT_EQ(wood.albedoTexture->image->width, 2);
  EXPECT_EQ(s.materials.at(s.shapes[1].material).albedoTexture, nullptr);  // unreadable: Kd alone, one line
  EXPECT_THAT(err, HasSubstr("1 texture not read"));
  EXPECT_THAT(err, HasSubstr("none.png"));
}

TEST(GltfTextures, UnreadableTextureIsSkippedWithOneLine) {
  // textures[1] is images[1], a missing file: the factor is used alone and one line says so.
  testing::internal::CaptureStderr();
  const MaterialDesc m =
      quadMaterial(writeQuad(R"({"emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 1}})", png2x2(0, 0)));
  const std::string err = testing::internal::GetCapturedStderr();
  expectColor(m.emission, Color(1.0f), 0);
  EXPECT_THAT(err, HasSubstr("quad.gltf: 1 texture not read, their factors used alone"));
  EXPECT_THAT(err, HasSubstr("missing.png is missing"));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST(TextureImage, DecodesPngAndRefusesOtherBytes) {
  const TextureImage t = decodeTextureImage(png2x2(255, 64), true);
  ASSERT_EQ(t.width, 2);
  ASSERT_EQ(t.height, 2);
  EXPECT_FLOAT_EQ(t.texel(1, 0)[0], 1.0f);
  EXPECT_NEAR(t.texel(0, 1)[1], srgb(64), 1e-7);
  EXPECT_FLOAT_EQ(t.texel(0, 1)[3], 1.0f);  // no alpha in the file: opaque
  EXPECT_NEAR(decodeTextureImage(png2x2(255, 64), false).texel(0, 1)[1], 64 / 255.0, 1e-7);
  EXPECT_THROW(decodeTextureImage("not an image", true), InputError);
  std::string truncated = png2x2(1, 2);
  truncated.resize(truncated.size() / 2);
  EXPECT_THROW(decodeTextureImage(truncated, true), InputError);
}

}  // namespace
}  // namespace firstshot
