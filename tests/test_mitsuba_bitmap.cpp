// Mitsuba bitmap and checkerboard textures (common/formats/mitsuba/mitsuba_texture.cpp): the same textures as JSON ones, value by value
// (image, decoding, filter, wrap modes, uv transform) in Mitsuba 3 and 0.6 spelling, nested and by reference; a bitmap
// with uscale on a rectangle rendered against the JSON quad within 3σ per 8 × 8 block; a bitmap where a constant is
// taken is its image's mean; bad textures named with element and line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>

#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/util/error.h"
#include "render/output/image_io.h"
#include "tests/block_compare.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

/// A 3 × 2 RGB image of distinct 8-bit values (rows from the top).
const uint8_t kRgb[18] = {10, 200, 30, 250, 40, 120, 90, 90, 90, 0, 255, 128, 60, 30, 220, 180, 180, 20};

/// The linear value of the sRGB code @p c ∈ [0, 1], computed here independently.
double srgb(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

/// A fresh folder holding t.png (kRgb), @p exr (3 × 2 float RGB texels f(kRgb[i] / 255), for JSON equivalents of
/// other decodings), checker.exr (Mitsuba's checkerboard of two colours as 2 × 2 texels) and quad.obj (a unit quad
/// with texture coordinates, vt flipped alike by Mitsuba and firstshot).
struct Folder {
  std::string dir = test::tempDir();
  Folder() {
    image::writePng(dir + "/t.png", 3, 2, kRgb);
    test::writeText(dir + "/quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
    const float c0[3] = {0.125f, 0.25f, 0.375f}, c1[3] = {0.875f, 0.875f, 0.875f};
    std::vector<float> checker;
    for (const float* c : {c0, c1, c1, c0}) checker.insert(checker.end(), c, c + 3);
    image::writeExr(dir + "/checker.exr", 2, 2, {"R", "G", "B"}, checker.data());
  }
  void exr(const std::string& name, double (*f)(double)) const {
    std::vector<float> v;
    for (uint8_t b : kRgb) v.push_back(float(f(b / 255.0)));
    image::writeExr(dir + "/" + name, 3, 2, {"R", "G", "B"}, v.data());
  }
  SceneDesc xml(const std::string& body, const char* version = "3.0.0") const {
    test::writeText(dir + "/scene.xml", fmt::format("<scene version=\"{}\">\n{}\n</scene>\n", version, body));
    return loadScene(dir + "/scene.xml");
  }
  SceneDesc json(const std::string& text) const {
    test::writeText(dir + "/scene.json", text);
    return loadScene(dir + "/scene.json");
  }
};

/// One quad OBJ shape per bsdf in @p bsdfs (XML), each its own material.
std::string xmlQuads(std::initializer_list<std::string> bsdfs) {
  std::string s;
  for (const std::string& b : bsdfs) s += R"(<shape type="obj"><string name="filename" value="quad.obj"/>)" + b + "</shape>\n";
  return s;
}

/// A JSON scene of one quad mesh per material in @p materials (JSON objects), lit by a point light.
std::string jsonQuads(std::initializer_list<std::string> materials) {
  std::string m, s;
  int k = 0;
  for (const std::string& x : materials) {
    m += fmt::format("{}\"m{}\": {}", k ? ", " : "", k, x);
    s += fmt::format(R"({}{{"type": "mesh", "file": "quad.obj", "material": "m{}"}})", k ? ", " : "", k);
    ++k;
  }
  return R"({"materials": {)" + m + R"(}, "shapes": [)" + s + R"(], "lights": [{"type": "point", "position": [0, 0, 1], "power": 1}]})";
}

/// The same texture: image (size and texels), filter, wrap modes and transform.
void expectSameTexture(const Texture& a, const Texture& b, const std::string& what) {
  EXPECT_EQ(a.filter, b.filter) << what;
  EXPECT_EQ(a.wrapU, b.wrapU) << what;
  EXPECT_EQ(a.wrapV, b.wrapV) << what;
  EXPECT_NEAR(a.transform.rotation, b.transform.rotation, 1e-6) << what;
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(a.transform.scale[i], b.transform.scale[i], 1e-6) << what;
    EXPECT_NEAR(a.transform.offset[i], b.transform.offset[i], 1e-6) << what;
  }
  ASSERT_EQ(a.image->width, b.image->width) << what;
  ASSERT_EQ(a.image->height, b.image->height) << what;
  for (size_t i = 0; i < a.image->texels.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.image->texels[i][c], b.image->texels[i][c], 2e-6) << what << " texel " << i;
}

/// Every shape's material of @p x and @p j: the same type, factors and albedo texture.
void expectSameTextures(const SceneDesc& x, const SceneDesc& j) {
  ASSERT_EQ(x.shapes.size(), j.shapes.size());
  for (size_t s = 0; s < x.shapes.size(); ++s) {
    const MaterialDesc &a = x.materials[x.shapes[s].material], &b = j.materials[j.shapes[s].material];
    const std::string what = "shape " + std::to_string(s);
    EXPECT_EQ(a.type, b.type) << what;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.albedo[c], b.albedo[c], 1e-6) << what;
    EXPECT_NEAR(a.metallic, b.metallic, 1e-6) << what;
    EXPECT_NEAR(a.roughness, b.roughness, 1e-6) << what;
    EXPECT_NEAR(a.ior, b.ior, 1e-6) << what;
    ASSERT_EQ(bool(a.albedoTexture), bool(b.albedoTexture)) << what;
    if (a.albedoTexture) expectSameTexture(*a.albedoTexture, *b.albedoTexture, what);
  }
}

size_t count(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t p = text.find(part); p != std::string::npos; p = text.find(part, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(MitsubaBitmap, TexturesMatchJson) {
  const Folder f;
  f.exr("linear.exr", [](double v) { return v; });
  testing::internal::CaptureStderr();
  const SceneDesc x = f.xml(R"(
    <texture type="bitmap" id="shared"><string name="filename" value="t.png"/><string name="filter_type" value="nearest"/>
      <string name="wrap_mode" value="clamp"/></texture>
    )" + xmlQuads({R"(<bsdf type="diffuse"><ref name="reflectance" id="shared"/></bsdf>)",
                   R"(<bsdf type="twosided"><bsdf type="diffuse"><ref name="reflectance" id="shared"/></bsdf></bsdf>)",
                   R"(<bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="t.png"/>
                        <string name="wrap_mode" value="mirror"/>
                        <transform name="to_uv"><scale x="2" y="3"/><rotate z="1" angle="90"/><translate x="0.5" y="0.25"/></transform>
                      </texture></bsdf>)",
                   R"(<bsdf type="roughplastic"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/>
                        <texture type="bitmap" name="diffuse_reflectance"><string name="filename" value="t.png"/>
                        <boolean name="raw" value="true"/></texture></bsdf>)",
                   R"(<bsdf type="principled"><texture type="checkerboard" name="base_color"><rgb name="color0" value="0.125, 0.25, 0.375"/>
                        <rgb name="color1" value="0.875"/><transform name="to_uv"><scale value="4"/></transform></texture></bsdf>)"}));
  const std::string err = testing::internal::GetCapturedStderr();
  // Mitsuba's to_uv maps uv to T·R(90° counter-clockwise)·S·uv; the JSON's rotation turns the other way (glTF's sense).
  const SceneDesc j = f.json(jsonQuads(
      {R"({"type": "diffuse", "albedo_texture": {"file": "t.png", "filter": "nearest", "wrap": "clamp"}})",
       R"({"type": "diffuse", "albedo_texture": {"file": "t.png", "filter": "nearest", "wrap": "clamp"}})",
       R"({"type": "diffuse", "albedo_texture": {"file": "t.png", "wrap": "mirror", "scale": [2, 3], "rotation": -90, "offset": [0.5, 0.25]}})",
       fmt::format(R"({{"type": "pbr", "metallic": 0, "roughness": {}, "ior": 1.5, "base_color_texture": "linear.exr"}})", std::sqrt(0.1)),
       R"({"type": "pbr", "metallic": 0, "roughness": 0.5, "ior": 1.5,
           "base_color_texture": {"file": "checker.exr", "filter": "nearest", "scale": [4, 4]}})"}));
  expectSameTextures(x, j);
  // The texture by reference is read once and shared.
  EXPECT_EQ(x.materials[x.shapes[0].material].albedoTexture, x.materials[x.shapes[1].material].albedoTexture);
  EXPECT_THAT(err, Not(HasSubstr("bitmap textures approximated")));
  // The checkerboard is Mitsuba's: color0 where u and v lie in the same half of [0, 1).
  const Texture& c = *x.materials[x.shapes[4].material].albedoTexture;
  EXPECT_EQ(c.lookup(Vec2(0.1f / 4, 0.2f / 4)), Color(0.125f, 0.25f, 0.375f));
  EXPECT_EQ(c.lookup(Vec2(0.6f / 4, 0.9f / 4)), Color(0.125f, 0.25f, 0.375f));
  EXPECT_EQ(c.lookup(Vec2(0.6f / 4, 0.2f / 4)), Color(0.875f));
  EXPECT_EQ(c.lookup(Vec2(1.3f / 4, 0.6f / 4)), Color(0.875f));
}

TEST(MitsubaBitmap, Mitsuba06SpellingMatchesJson) {
  // Mitsuba 0.6: filterType (ewa: bilinear here, noted), wrapModeU / wrapModeV (zero: clamp, noted), uscale, vscale,
  // uoffset, voffset (uv ⊙ scale + offset), gamma (2.2: the stored values v read as v^2.2).
  const Folder f;
  f.exr("gamma.exr", [](double v) { return std::pow(v, 2.2); });
  f.exr("srgb.exr", srgb);
  testing::internal::CaptureStderr();
  const SceneDesc x = f.xml(xmlQuads({R"(<bsdf type="diffuse"><texture type="bitmap" name="reflectance">
        <string name="filename" value="t.png"/><string name="filterType" value="ewa"/><string name="wrapModeU" value="mirror"/>
        <string name="wrapModeV" value="zero"/><float name="uscale" value="2"/><float name="vscale" value="0.5"/>
        <float name="uoffset" value="0.25"/><float name="gamma" value="2.2"/></texture></bsdf>)",
      R"(<bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="t.png"/>
        <string name="filterType" value="trilinear"/><string name="wrapMode" value="one"/><float name="voffset" value="-1"/>
        <float name="gamma" value="-1"/></texture></bsdf>)"}), "0.6.0");
  const std::string err = testing::internal::GetCapturedStderr();
  const SceneDesc j = f.json(jsonQuads(
      {R"({"type": "diffuse", "albedo_texture": {"file": "gamma.exr", "wrap": ["mirror", "clamp"], "scale": [2, 0.5], "offset": [0.25, 0]}})",
       R"({"type": "diffuse", "albedo_texture": {"file": "srgb.exr", "wrap": "clamp", "offset": [0, -1]}})"}));
  expectSameTextures(x, j);
  EXPECT_EQ(count(err, "bitmap filter_type ewa approximated"), 1u) << err;
  EXPECT_EQ(count(err, "bitmap filter_type trilinear approximated"), 1u) << err;
  EXPECT_EQ(count(err, "wrap modes zero and one approximated by clamp"), 1u) << err;
}

TEST(MitsubaBitmap, RectangleCoordinatesAreMitsubas) {
  // Mitsuba's rectangle: (u, v) = ((x + 1)/2, (y + 1)/2) on [−1, 1]², so (0, 0) at the corner (−1, −1).
  const Folder f;
  const SceneDesc s = f.xml(R"(<shape type="rectangle"><transform name="to_world"><scale value="2"/></transform></shape>
      <shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>)");
  ASSERT_EQ(s.shapes.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const ShapeDesc& r = s.shapes[i];
    const double scale = i == 0 ? 2.0 : 1.0;
    ASSERT_TRUE(r.hasUv());
    for (size_t face = 0; face < r.faces.size(); ++face)
      for (int k = 0; k < r.faces[face].count; ++k) {
        const Vec3d p = r.vertices[r.faces[face].v[k]] / scale;
        const Vec2 uv = r.cornerUv(face, k);
        EXPECT_NEAR(uv.x, (p.x + 1) / 2, 1e-6) << r.name;
        EXPECT_NEAR(uv.y, (p.y + 1) / 2, 1e-6) << r.name;
      }
  }
}

TEST(MitsubaBitmap, BitmapWithUscaleOnARectangleRendersAsJson) {
  // A floor (Mitsuba's rectangle, scaled by 1.5 and turned to face +y) with a nearest, mirrored bitmap tiled by
  // uscale 2 and vscale 1.5, lit by an area light. The JSON quad has the same corners, whose own coordinates are
  // (u, 1 − v) of Mitsuba's: the same lookups take scale [2, −1.5] and offset [0, 1.5].
  const Folder f;
  const SceneDesc x = f.xml(R"(
    <sensor type="perspective"><float name="fov" value="60"/>
      <transform name="to_world"><lookat origin="0, 1.8, 0" target="0, 0, 0" up="0, 0, -1"/></transform>
      <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/></film></sensor>
    <shape type="rectangle"><transform name="to_world"><scale value="1.5"/><rotate x="1" angle="-90"/></transform>
      <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="t.png"/>
        <string name="filter_type" value="nearest"/><string name="wrap_mode" value="mirror"/>
        <float name="uscale" value="2"/><float name="vscale" value="1.5"/></texture></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="2.2"/></transform>
      <emitter type="area"><rgb name="radiance" value="12"/></emitter></shape>)");
  const SceneDesc j = f.json(fmt::format(R"({{
    "camera": {{"position": [0, 1.8, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": {}, "resolution": [32, 24]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo_texture": {{"file": "t.png", "filter": "nearest", "wrap": "mirror",
                                                                   "scale": [2, -1.5], "offset": [0, 1.5]}}}},
                  "lamp": {{"type": "diffuse", "albedo": 0.5, "emission": 12}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-1.5, 0, 1.5], [1.5, 0, 1.5], [1.5, 0, -1.5], [-1.5, 0, -1.5]]}},
               {{"type": "quad", "material": "lamp", "vertices": [[-0.5, 2.2, -0.5], [0.5, 2.2, -0.5], [0.5, 2.2, 0.5], [-0.5, 2.2, 0.5]]}}]}})",
      glm::degrees(2 * std::atan(std::tan(glm::radians(30.0)) * 24 / 32))));
  const RenderScene rx(x, 0.5), rj(j, 0.5);
  IntegratorOptions io;
  io.maxDepth = 2;
  auto ix = makeIntegrator("path", io), ij = makeIntegrator("path", io);
  ix->preprocess(rx);
  ij->preprocess(rj);
  const auto bx = test::blockMeans(*ix, rx, 48, 3), bj = test::blockMeans(*ij, rj, 48, 4);
  test::expectBlocksAgree("bitmap with uscale on a rectangle", bx, bj);
  // The image is not flat (the texture shows): the blocks' means spread by more than 20% of their mean.
  double lo = 1e30, hi = 0;
  for (const auto& b : bx) lo = std::min(lo, b.mean()), hi = std::max(hi, b.mean());
  EXPECT_GT(hi - lo, 0.2 * hi);
}

TEST(MitsubaBitmap, BitmapWhereAConstantIsTakenIsItsMean) {
  // A glass's specular_transmittance takes a constant: the image's mean (sRGB-decoded), noted once.
  const Folder f;
  testing::internal::CaptureStderr();
  const SceneDesc x = f.xml(R"(<shape type="cube"><bsdf type="dielectric"><texture type="bitmap" name="specular_transmittance">
      <string name="filename" value="t.png"/></texture></bsdf></shape>)");
  const std::string err = testing::internal::GetCapturedStderr();
  for (int c = 0; c < 3; ++c) {
    double mean = 0;
    for (int i = 0; i < 6; ++i) mean += srgb(kRgb[3 * i + c] / 255.0) / 6;
    EXPECT_NEAR(x.materials[0].transmittance[c], mean, 1e-6);
  }
  EXPECT_EQ(count(err, "replaced by their image's mean"), 1u) << err;
}

TEST(MitsubaBitmap, BadTexturesAreNamed) {
  const Folder f;
  const std::pair<const char*, const char*> cases[] = {
      {R"(<string name="filename" value="t.png"/><string name="filter_type" value="cubic"/>)", "unknown filter_type \"cubic\""},
      {R"(<string name="filename" value="t.png"/><string name="wrap_mode" value="wrap"/>)", "unknown wrap mode \"wrap\""},
      {R"(<string name="filename" value="none.png"/>)", "texture file not found"},
      {R"(<string name="filename" value="t.png"/><float name="gamma" value="0"/>)", "gamma must be"},
      {R"(<string name="filename" value="t.png"/><transform name="to_uv"><matrix value="1 1 0 0 1 0 0 1 1"/></transform>)", "no shear"},
      {"", "a bitmap needs"}};
  for (const auto& [inside, message] : cases) {
    SCOPED_TRACE(message);
    try {
      f.xml(std::string("<shape type=\"cube\">\n<bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">") + inside +
            "</texture></bsdf></shape>");
      ADD_FAILURE() << "not refused";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("scene.xml: scene/shape/bsdf/reflectance"));
      EXPECT_THAT(e.what(), HasSubstr("(line 4)"));
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  }
  try {
    f.xml(R"(<shape type="cube"><bsdf type="diffuse"><texture type="gradient" name="reflectance"/></bsdf></shape>)");
    ADD_FAILURE() << "an unknown texture type must be refused";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("texture type \"gradient\" is not supported"));
  }
}
