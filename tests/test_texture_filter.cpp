// Texture filters and wrap modes (common/materials/texture.h): a nearest 2 × 2 checker keeps its texels sharp where the bilinear
// lookup blends them; every wrap mode at u = −0.25 and 1.25 against values worked out by hand, for both filters; the
// glTF sampler's magFilter / minFilter and wrapS / wrapT read from a file, down to the renderer's per-point albedo;
// the JSON texture's "filter" and per-axis "wrap"; both item-buffer back ends cut a nearest alpha texture as the CPU does.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>

#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/patches/patch_cutouts.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/gl/gl_item_buffer.h"
#include "render/output/image_io.h"
#include "render/scene/surface_textures.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

const Color kBlack(0.0f), kWhite(1.0f);

/// A 2 × 2 checker: black top left and bottom right, white elsewhere.
Texture checker(TextureFilter filter) {
  Texture t;
  t.image = std::make_shared<const TexelImage>(makeTexelImage(2, 2, {kBlack, kWhite, kWhite, kBlack}, "checker"));
  t.filter = filter;
  return t;
}

TEST(TextureFilter, NearestCheckerKeepsItsTexelsSharp) {
  const Texture nearest = checker(TextureFilter::Nearest), linear = checker(TextureFilter::Linear);
  // Texel centres: exact for both filters.
  for (const Texture* t : {&nearest, &linear}) {
    EXPECT_EQ(t->lookup(Vec2(0.25f, 0.25f)), kBlack);
    EXPECT_EQ(t->lookup(Vec2(0.75f, 0.25f)), kWhite);
    EXPECT_EQ(t->lookup(Vec2(0.25f, 0.75f)), kWhite);
    EXPECT_EQ(t->lookup(Vec2(0.75f, 0.75f)), kBlack);
  }
  // Between the centres: nearest gives one texel or the other, never a blend; bilinear blends (0.5 half way).
  int blends = 0;
  for (int i = 0; i <= 400; ++i) {
    const Vec2 uv(float(i) / 400.0f, 0.3f + 0.4f * float(i % 7) / 7.0f);
    const Color c = nearest.lookup(uv);
    EXPECT_TRUE(c == kBlack || c == kWhite) << "u = " << uv.x << ", v = " << uv.y << ": " << c.x;
    const Color l = linear.lookup(uv);
    blends += l.x > 0.01f && l.x < 0.99f;
  }
  EXPECT_GT(blends, 300) << "the bilinear lookup blends between centres (the test sees the difference)";
  EXPECT_EQ(nearest.lookup(Vec2(0.49f, 0.25f)), kBlack);
  EXPECT_EQ(nearest.lookup(Vec2(0.51f, 0.25f)), kWhite);
  EXPECT_FLOAT_EQ(linear.lookup(Vec2(0.5f, 0.25f)).x, 0.5f);
  // The alpha lookup follows the same filter.
  EXPECT_EQ(nearest.alphaLookup(Vec2(0.45f, 0.25f)), 0.0f);
  EXPECT_EQ(nearest.alphaLookup(Vec2(0.55f, 0.25f)), 1.0f);
  EXPECT_NE(nearest.hash(), linear.hash());
}

TEST(TextureFilter, WrapModesAtMinusAQuarterAndOneAndAQuarter) {
  // A 3 × 1 ramp 0, ½, 1: texel i covers u ∈ [i/3, (i+1)/3), its centre at (i + ½)/3.
  Texture t;
  t.image = std::make_shared<const TexelImage>(makeTexelImage(3, 1, {Color(0.0f), Color(0.5f), Color(1.0f)}, "ramp"));
  struct Case {
    TextureWrap wrap;
    TextureFilter filter;
    float atMinusQuarter, atOneAndQuarter;
  };
  // Repeat reads u = 0.75 and 0.25; mirror reads u = 0.25 and 0.75; clamp holds the edge texels. Bilinear at
  // u = 0.75: 1.75 texel widths from the left edge, ¾ of the way from centre 1 (½) to centre 2 (1): 0.875; at 0.25:
  // ¼ of the way from centre 0 (0) to centre 1: 0.125. Nearest: u = 0.75 lies in texel 2, u = 0.25 in texel 0.
  const Case cases[] = {
      {TextureWrap::Repeat, TextureFilter::Linear, 0.875f, 0.125f},
      {TextureWrap::MirroredRepeat, TextureFilter::Linear, 0.125f, 0.875f},
      {TextureWrap::ClampToEdge, TextureFilter::Linear, 0.0f, 1.0f},
      {TextureWrap::Repeat, TextureFilter::Nearest, 1.0f, 0.0f},
      {TextureWrap::MirroredRepeat, TextureFilter::Nearest, 0.0f, 1.0f},
      {TextureWrap::ClampToEdge, TextureFilter::Nearest, 0.0f, 1.0f},
  };
  for (const Case& c : cases) {
    t.wrapU = c.wrap, t.filter = c.filter;
    const std::string what = "wrap " + std::to_string(int(c.wrap)) + ", filter " + std::to_string(int(c.filter));
    EXPECT_NEAR(t.lookup(Vec2(-0.25f, 0.5f)).x, c.atMinusQuarter, 1e-6) << what << " at u = -0.25";
    EXPECT_NEAR(t.lookup(Vec2(1.25f, 0.5f)).x, c.atOneAndQuarter, 1e-6) << what << " at u = 1.25";
  }
}

/// Writes quad.gltf in a fresh folder: one unit quad in z = 0 with texture coordinates [0, 1]² per sampler of
/// @p samplers (JSON, "" for a texture without one), material "m<k>" of base colour the 2 × 2 checker PNG (sRGB 0 and
/// 255) through texture k and sampler k. @return its path.
std::string writeCheckerQuads(const std::vector<std::string>& samplers) {
  const std::string dir = test::tempDir();
  const uint8_t rgb[12] = {0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0};
  image::writePng(dir + "/checker.png", 2, 2, rgb);
  const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, uvs[8] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(uvs), sizeof uvs).append(reinterpret_cast<const char*>(indices), sizeof indices);
  test::writeText(dir + "/quad.bin", bin);
  std::string nodes, meshes, materials, textures, list;
  for (size_t k = 0; k < samplers.size(); ++k) {
    const std::string c = k ? ", " : "", i = std::to_string(k);
    nodes += c + R"({"mesh": )" + i + "}";
    list += c + i;
    meshes += c + R"({"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": )" + i + "}]}";
    materials += c + R"({"name": "m)" + i + R"(", "pbrMetallicRoughness": {"baseColorTexture": {"index": )" + i +
                 R"(}, "metallicFactor": 0}})";
    textures += c + R"({"source": 0)" + (samplers[k].empty() ? "" : R"(, "sampler": )" + i) + "}";
  }
  std::string samplerList;
  for (size_t k = 0; k < samplers.size(); ++k) samplerList += (k ? ", " : "") + (samplers[k].empty() ? "{}" : samplers[k]);
  test::writeText(dir + "/quad.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [)" + list + R"(]}],
  "nodes": [)" + nodes + R"(], "meshes": [)" + meshes + R"(], "materials": [)" + materials + R"(],
  "textures": [)" + textures + R"(], "samplers": [)" + samplerList + R"(],
  "images": [{"uri": "checker.png"}],
  "buffers": [{"uri": "quad.bin", "byteLength": 92}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                  {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]})");
  return dir + "/quad.gltf";
}

TEST(TextureFilter, GltfSamplerFiltersAndWrapModes) {
  // glTF 2.0's codes: NEAREST 9728, LINEAR 9729, NEAREST_MIPMAP_NEAREST 9984, LINEAR_MIPMAP_NEAREST 9985,
  // NEAREST_MIPMAP_LINEAR 9986, LINEAR_MIPMAP_LINEAR 9987; REPEAT 10497, CLAMP_TO_EDGE 33071, MIRRORED_REPEAT 33648.
  const std::vector<std::pair<std::string, TextureFilter>> filters = {
      {"", TextureFilter::Linear},
      {"{}", TextureFilter::Linear},
      {R"({"magFilter": 9728})", TextureFilter::Nearest},
      {R"({"magFilter": 9729, "minFilter": 9728})", TextureFilter::Linear},  // magnification is what a texel shows
      {R"({"magFilter": 9728, "minFilter": 9987})", TextureFilter::Nearest},
      {R"({"minFilter": 9986})", TextureFilter::Nearest},  // no magFilter: the min filter's within a level
      {R"({"minFilter": 9984})", TextureFilter::Nearest},
      {R"({"minFilter": 9985})", TextureFilter::Linear},
      {R"({"minFilter": 9729})", TextureFilter::Linear},
      {R"({"magFilter": 9728, "wrapS": 33648, "wrapT": 33071})", TextureFilter::Nearest},
      {R"({"wrapS": 10497, "wrapT": 33648})", TextureFilter::Linear}};
  std::vector<std::string> samplers;
  for (const auto& f : filters) samplers.push_back(f.first);
  const SceneDesc s = loadScene(writeCheckerQuads(samplers));
  ASSERT_EQ(s.shapes.size(), filters.size());
  std::vector<std::shared_ptr<const Texture>> byIndex(filters.size());
  for (const ShapeDesc& shape : s.shapes) {
    const MaterialDesc& m = s.materials.at(shape.material);
    ASSERT_EQ(m.name.substr(0, 1), "m");
    byIndex.at(std::stoul(m.name.substr(1))) = m.albedoTexture;
  }
  for (size_t k = 0; k < filters.size(); ++k) {
    SCOPED_TRACE(filters[k].first);
    ASSERT_TRUE(byIndex[k]);
    EXPECT_EQ(byIndex[k]->filter, filters[k].second);
  }
  EXPECT_EQ(byIndex[9]->wrapU, TextureWrap::MirroredRepeat);
  EXPECT_EQ(byIndex[9]->wrapV, TextureWrap::ClampToEdge);
  EXPECT_EQ(byIndex[10]->wrapU, TextureWrap::Repeat);
  EXPECT_EQ(byIndex[10]->wrapV, TextureWrap::MirroredRepeat);
}

TEST(TextureFilter, GltfNearestCheckerStaysSharpOnTheSurface) {
  // The renderer's albedo at points of the quad (render/scene/surface_textures.h): with NEAREST every point has the
  // base colour of a texel (metallic 0: the diffuse part 0.96 × texel), with LINEAR those between centres do not.
  for (const bool nearest : {true, false}) {
    SCOPED_TRACE(nearest ? "NEAREST" : "LINEAR");
    SceneDesc s = loadScene(writeCheckerQuads({nearest ? R"({"magFilter": 9728, "minFilter": 9728})" : R"({"magFilter": 9729})"}));
    const PatchMesh mesh = buildPatches(s, kFacesAsTheyAre);
    const SurfaceTextures textures(s, mesh);
    ASSERT_TRUE(textures.textured(0));
    const float white = s.materials[0].albedo.x;  // the factor's diffuse part
    ASSERT_GT(white, 0.9f);
    int between = 0, points = 0;
    for (uint32_t patch = 0; patch < mesh.size(); ++patch) {  // points spread over each triangle
      const Patch& q = mesh.patches[patch];
      for (int i = 0; i < 40; ++i)
        for (int j = 0; i + j < 40; ++j) {
          const float a = (i + 0.3f) / 40.5f, b = (j + 0.3f) / 40.5f;
          const Vec3 p = q.v[0] + a * (q.v[1] - q.v[0]) + b * (q.v[2] - q.v[0]);
          const float albedo = textures.albedoAt(patch, p).x;
          const bool sharp = std::abs(albedo) < 1e-6f || std::abs(albedo - white) < 1e-5f * white;
          between += !sharp, ++points;
          // The texel under the point (y up is v down): black where x and y lie on the same side of ½.
          if (nearest && std::abs(p.x - 0.5f) > 1e-4f && std::abs(p.y - 0.5f) > 1e-4f) {
            EXPECT_NEAR(albedo, (p.x < 0.5f) == (p.y < 0.5f) ? white : 0.0f, 1e-5f) << p.x << ", " << p.y;
          }
        }
    }
    if (nearest) EXPECT_EQ(between, 0);
    else EXPECT_GT(between, points / 2);
  }
}

TEST(TextureFilter, JsonFilterAndWrapPerAxis) {
  const std::string dir = test::tempDir();
  const uint8_t rgb[12] = {0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0};
  image::writePng(dir + "/checker.png", 2, 2, rgb);
  const auto scene = [&](const std::string& texture) {
    test::writeText(dir + "/scene.json", R"({"materials": {"m": {"type": "diffuse", "albedo_texture": )" + texture + R"(}},
      "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}],
      "lights": [{"type": "point", "position": [0, 0, 1], "power": 1}]})");
    return loadScene(dir + "/scene.json");
  };
  const SceneDesc s = scene(R"({"file": "checker.png", "filter": "nearest", "wrap": ["mirror", "clamp"]})");
  const Texture& t = *s.materials[0].albedoTexture;
  EXPECT_EQ(t.filter, TextureFilter::Nearest);
  EXPECT_EQ(t.wrapU, TextureWrap::MirroredRepeat);
  EXPECT_EQ(t.wrapV, TextureWrap::ClampToEdge);
  EXPECT_EQ(scene(R"({"file": "checker.png"})").materials[0].albedoTexture->filter, TextureFilter::Linear);
  for (const char* bad : {R"({"file": "checker.png", "filter": "cubic"})", R"({"file": "checker.png", "wrap": ["mirror"]})"}) {
    try {
      scene(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("materials.m.albedo_texture"));
    }
  }
}

TEST(TextureFilter, ItemBuffersCutANearestAlphaTextureAsTheCpu) {
  // A screen over a floor, masked (cut-off ½) by a 2 × 1 alpha texture 0.2 | 0.6 along u = x/2 + ½ (repeated):
  // nearest, the screen exists where u ∈ [½, 1), half of it; bilinear, where alpha = 0.2 + 0.8·|u − ¼| folded reaches ½,
  // u ∈ [0.625, 0.875], a quarter. An orthographic view straight down, both back ends, and the CPU's own test.
  for (const TextureFilter filter : {TextureFilter::Nearest, TextureFilter::Linear}) {
    SceneDesc desc = test::sceneFromJson(R"({
      "materials": {"floor": {"type": "diffuse", "albedo": 0.5}, "screen": {"type": "diffuse", "albedo": 0.5, "alpha_mode": "mask"}},
      "shapes": [{"type": "quad", "material": "floor", "vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]},
                 {"type": "quad", "material": "screen", "vertices": [[-1, 1, 1], [1, 1, 1], [1, 1, -1], [-1, 1, -1]]}],
      "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": 1}],
      "settings": {"patch_size": 0.5}})");
    TexelImage im = makeTexelImage(2, 1, {Color(1.0f), Color(1.0f)}, "alpha");
    im.alpha = {0.2f, 0.6f};
    auto t = std::make_shared<Texture>();
    t->image = std::make_shared<const TexelImage>(std::move(im));
    t->filter = filter;
    desc.materials[size_t(desc.findMaterial("screen"))].alphaTexture = t;
    const PatchMesh mesh = buildPatches(desc, 0.5);
    ItemGeometry geometry = ItemGeometry::fromPatches(mesh);
    geometry.cutouts = PatchCutouts::build(desc, mesh);
    ASSERT_NE(geometry.cutouts, nullptr);
    View view;
    view.projection = Projection::Orthographic;
    view.eye = Vec3d(0, 2, 0), view.forward = Vec3d(0, -1, 0), view.right = Vec3d(1, 0, 0), view.up = Vec3d(0, 0, -1);
    view.width = view.height = 64;  // over [−1, 1]²: the screen
    const uint32_t screen = uint32_t(desc.findMaterial("screen"));
    const double expected = filter == TextureFilter::Nearest ? 0.5 : 0.25;
    for (const std::string backend : {"gl", "embree"}) {
      std::unique_ptr<ItemBufferRenderer> r;
      if (backend == "gl") r = std::make_unique<GLItemBuffer>(geometry, geometry.bounds);
      else r = std::make_unique<EmbreeItemBuffer>(geometry, geometry.bounds);
      std::vector<uint32_t> ids;
      r->render(view, ids);
      int onScreen = 0;
      for (const uint32_t p : ids) onScreen += p != kNoPatch && mesh.patches[p].material == screen;
      EXPECT_NEAR(onScreen / double(ids.size()), expected, 1.5 / view.width) << backend << " filter " << int(filter);
    }
  }
}

}  // namespace
}  // namespace firstshot
