// Shading normals: corner normals interpolated by barycentric coordinates, normal maps in the generated
// tangent frame (the shading they give against Lambert's law), the geometric side rule, normals read from glTF and
// OBJ files, a smooth low-poly sphere without facet edges, light tracing and BDPT against path tracing (the adjoint
// correction), first-shot against NEE on scenes/normal-map.json, and images that do not depend on the thread count.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/scene/scene_shapes.h"
#include "tests/bias_util.h"
#include "tests/block_compare.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// The plane y = 0 (2 m × 2 m quad, natural texture coordinates u = (z + 1)/2, v = (1 − x)/2: ∂p/∂u = +z and the
/// image's up, −∂p/∂v, = +x) seen from 3 m above, lit by a directional light travelling along @p direction.
SceneDesc plane(const Vec3& direction = Vec3(0, -1, 0)) {
  return test::sceneFromJson(fmt::format(R"({{
    "camera": {{"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30, "resolution": [16, 16]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": 0.8}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}}],
    "lights": [{{"type": "directional", "direction": [{}, {}, {}], "irradiance": 2}}]}})",
                                         direction.x, direction.y, direction.z));
}

/// A normal map of one texel, the tangent-space unit normal @p n (texel (n + 1)/2, linear).
std::shared_ptr<const Texture> constantNormalMap(const Vec3& n) {
  auto t = std::make_shared<Texture>();
  t->image = std::make_shared<const TexelImage>(makeTexelImage(1, 1, {(n + Vec3(1.0f)) * 0.5f}, "tilt"));
  return t;
}

/// A hit at @p p on patch 0 (the scene's first face, traced as it is) with geometric normal @p ng.
Hit hitOn(const Vec3& p, const Vec3& ng) {
  Hit h;
  h.p = p, h.ng = ng, h.patch = 0;
  return h;
}

TEST(ShadingNormals, CornerNormalsInterpolatedByBarycentrics) {
  SceneDesc desc = plane();
  const std::vector<Vec3> corners = {glm::normalize(Vec3(0.3f, 1, 0)), glm::normalize(Vec3(0, 1, 0.4f)),
                                     glm::normalize(Vec3(-0.2f, 1, -0.1f)), glm::normalize(Vec3(0.1f, 1, 0.3f))};
  desc.shapes[0].normals = corners;
  const RenderScene scene(desc);
  const ShapeDesc& s = scene.desc().shapes[0];
  const auto v = [&](int k) { return Vec3(s.vertices[s.faces[0].v[k]]); };
  // Points of triangle (0, 1, 2) and of (0, 2, 3) at known barycentric coordinates (β, γ).
  for (const auto& [a, b, c, beta, gamma] : {std::tuple{0, 1, 2, 0.2f, 0.5f}, std::tuple{0, 1, 2, 0.6f, 0.1f},
                                              std::tuple{0, 2, 3, 0.3f, 0.6f}, std::tuple{0, 2, 3, 0.1f, 0.2f}}) {
    const Vec3 p = v(a) + beta * (v(b) - v(a)) + gamma * (v(c) - v(a));
    const Vec3 expected = glm::normalize(corners[a] + beta * (corners[b] - corners[a]) + gamma * (corners[c] - corners[a]));
    const Vec3 n = scene.shadingNormal(hitOn(p, Vec3(0, 1, 0)));
    test::expectNear(n, expected, 1e-5f, fmt::format("triangle ({}, {}, {}) at ({}, {})", a, b, c, beta, gamma));
  }
  // Without normals: the geometric normal, the same bits.
  const RenderScene flat(plane());
  EXPECT_EQ(flat.shadingNormal(hitOn(Vec3(0.1f, 0, 0.2f), Vec3(0, 1, 0))), Vec3(0, 1, 0));
  EXPECT_TRUE(flat.shadingNormals().empty());
}

TEST(ShadingNormals, GeneratedTangentFrameFollowsTheTextureCoordinates) {
  // A texel tilted by 40° towards tangent-space +x must tilt the normal towards ∂p/∂u (+z), one towards +y
  // towards the image's up, −∂p/∂v (+x); the normal scale multiplies x and y.
  const float t = glm::radians(40.0f);
  for (const auto& [texel, scale, expected] :
       {std::tuple{Vec3(std::sin(t), 0, std::cos(t)), 1.0f, Vec3(0, std::cos(t), std::sin(t))},
        std::tuple{Vec3(0, std::sin(t), std::cos(t)), 1.0f, Vec3(std::sin(t), std::cos(t), 0)},
        std::tuple{Vec3(std::sin(t), 0, std::cos(t)), 0.5f,
                   glm::normalize(Vec3(0, std::cos(t), 0.5f * std::sin(t)))}}) {
    SceneDesc desc = plane();
    desc.materials[0].normalTexture = constantNormalMap(texel);
    desc.materials[0].normalScale = scale;
    const RenderScene scene(desc);
    for (const Vec3& p : {Vec3(0.3f, 0, -0.5f), Vec3(-0.7f, 0, 0.6f)})  // both triangles of the quad
      test::expectNear(scene.shadingNormal(hitOn(p, Vec3(0, 1, 0))), expected, 2e-3f,
                 fmt::format("texel ({}, {}, {}) scale {}", texel.x, texel.y, texel.z, scale));
  }
}

TEST(ShadingNormals, NormalMapTiltsLambertShadingAsComputed) {
  // The plane lit by a directional light of irradiance E = 2 W/m² from 30° off the vertical towards +z, its normal
  // map tilting the normal by 40° towards +z (tangent +x): each pixel is ρ/π · E · cos 10°, not ρ/π · E · cos 30°.
  const float tilt = glm::radians(40.0f), light = glm::radians(30.0f);
  SceneDesc desc = plane(Vec3(0, -std::cos(light), -std::sin(light)));
  desc.materials[0].normalTexture = constantNormalMap(Vec3(std::sin(tilt), 0, std::cos(tilt)));
  const double expected = 0.8 / kPi * 2.0 * std::cos(double(tilt) - double(light));
  IntegratorOptions io;
  io.maxDepth = 1;
  const RenderScene scene(desc);
  const Film film = test::renderPath(scene, io, 4).film;
  const std::vector<double> e(16 * 16, expected);
  const test::Comparison r = test::compareImage(film, e, 1, 8, 1e-4 * expected);
  fmt::print("normal-mapped plane: mean {:.6f}, expected {:.6f} (flat: {:.6f})\n", r.meanExpected + r.meanDiff, expected,
             0.8 / kPi * 2.0 * std::cos(light));
  EXPECT_LE(std::abs(r.meanDiff), 1e-4 * expected);
  EXPECT_LE(r.maxAbsDiff, 1e-4 * expected);
}

TEST(ShadingNormals, DirectionsOnDifferentSidesOfTheTwoNormalsGetNothing) {
  // A Lambertian BSDF whose shading normal is tilted 30° from the geometric one: a direction above the shading
  // horizon but below the geometric one (or the reverse) is 0 to eval, and sample() never returns one.
  BSDF b = LambertBRDF{Color(0.5f)};
  const float t = glm::radians(30.0f);
  b.setGeometricNormal(Vec3(std::sin(t), 0, std::cos(t)));  // ng in the shading frame
  const Vec3 wo = glm::normalize(Vec3(0, 0.3f, 1));
  const Vec3 belowGeometric = glm::normalize(Vec3(-1, 0, 0.3f));  // z > 0, dot with ng < 0
  EXPECT_GT(belowGeometric.z, 0.0f);
  EXPECT_EQ(b.eval(BSDFQuery(belowGeometric, wo)), Color(0.0f));
  EXPECT_GT(b.eval(BSDFQuery(glm::normalize(Vec3(1, 0, 0.3f)), wo)).x, 0.0f);
  EXPECT_FALSE(b.isDiffuse());
  EXPECT_EQ(b.diffuseAlbedo(), Color(0.0f));
  int rejected = 0;
  for (int i = 0; i < 1024; ++i) {
    BSDFQuery q(wo);
    const Color w = b.sample(q, Vec2((i % 32 + 0.5f) / 32, (i / 32 + 0.5f) / 32));
    if (q.pdf > 0.0f) {
      EXPECT_GT(glm::dot(q.wi, Vec3(std::sin(t), 0, std::cos(t))), 0.0f);
    } else {
      ++rejected;
      EXPECT_EQ(w, Color(0.0f));
    }
  }
  EXPECT_GT(rejected, 0);  // the cosine lobe about the shading normal reaches below the geometric horizon
}

/// An icosphere (shapes::makeSphere, @p subdivisions) written as a glTF with POSITION, NORMAL (the sphere's) and
/// indices, in a fresh directory. @return the .gltf's path.
std::string writeSphereGltf(int subdivisions) {
  ShapeDesc s;
  shapes::makeSphere(s, Vec3d(0.0), 1.0, subdivisions);
  std::vector<float> positions, normals;
  for (const Vec3d& v : s.vertices)
    for (int c = 0; c < 3; ++c) positions.push_back(float(v[c])), normals.push_back(float(glm::normalize(v)[c]));
  std::vector<uint16_t> indices;
  for (const Face& f : s.faces)
    for (int k = 0; k < 3; ++k) indices.push_back(uint16_t(f.v[k]));
  std::string bin(reinterpret_cast<const char*>(positions.data()), positions.size() * 4);
  bin.append(reinterpret_cast<const char*>(normals.data()), normals.size() * 4);
  bin.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 2);
  const size_t n = s.vertices.size(), p = n * 12;
  const std::string dir = test::tempDir();
  test::writeText(dir + "/sphere.bin", bin);
  test::writeText(dir + "/sphere.gltf", fmt::format(R"({{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}], "meshes": [{{"name": "sphere", "primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2}}]}}],
  "buffers": [{{"uri": "sphere.bin", "byteLength": {}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {}}}, {{"buffer": 0, "byteOffset": {}, "byteLength": {}}},
                  {{"buffer": 0, "byteOffset": {}, "byteLength": {}}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {}, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]}},
                {{"bufferView": 1, "componentType": 5126, "count": {}, "type": "VEC3"}},
                {{"bufferView": 2, "componentType": 5123, "count": {}, "type": "SCALAR"}}]}})",
                                                    bin.size(), p, p, p, 2 * p, indices.size() * 2, n, n, indices.size()));
  return dir + "/sphere.gltf";
}

/// Mean |discrete Laplacian| of channel 1 over the pixels whose four neighbours are lit too, relative to their mean.
double roughness(const Film& film) {
  const int w = film.width(), h = film.height();
  double sum = 0, level = 0;
  int n = 0;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const double c = film.mean(x, y).y, l = film.mean(x - 1, y).y, r = film.mean(x + 1, y).y,
                   u = film.mean(x, y - 1).y, d = film.mean(x, y + 1).y;
      if (!(c > 0 && l > 0 && r > 0 && u > 0 && d > 0)) continue;
      sum += std::abs(4 * c - l - r - u - d), level += c, ++n;
    }
  return n > 0 ? sum / level : 0.0;
}

TEST(ShadingNormals, GltfNormalsRenderALowPolySphereSmooth) {
  // An 80-triangle icosphere from a glTF with NORMAL, lit by a directional light: its normals reach the shape, and
  // its image has no facet edges (the relative mean |Laplacian| inside the sphere falls well below the faceted one's).
  const std::string gltf = writeSphereGltf(1);
  const SceneDesc asset = loadScene(gltf);
  ASSERT_EQ(asset.shapes.size(), 1u);
  const ShapeDesc& s = asset.shapes[0];
  ASSERT_EQ(s.normals.size(), 4 * s.faces.size());
  for (size_t f = 0; f < s.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) test::expectNear(s.cornerNormal(f, k), Vec3(glm::normalize(s.vertices[s.faces[f].v[k]])), 1e-5f, "corner");
  SceneDesc smooth = test::sceneFromJson(fmt::format(R"({{
    "camera": {{"position": [0, 0, 3.2], "look_at": [0, 0, 0], "fov_y": 45, "resolution": [64, 64]}},
    "materials": {{"clay": {{"type": "diffuse", "albedo": 0.8}}}},
    "shapes": [{{"type": "mesh", "material": "clay", "file": "{}"}}],
    "lights": [{{"type": "directional", "direction": [-0.4, -0.5, -1], "irradiance": 3}}]}})", gltf));
  SceneDesc faceted = smooth;
  faceted.shapes[0].normals.clear();
  IntegratorOptions io;
  io.maxDepth = 1;
  const RenderScene a(smooth), b(faceted);
  const double rs = roughness(test::renderPath(a, io, 16).film), rf = roughness(test::renderPath(b, io, 16).film);
  fmt::print("relative mean |Laplacian|: smooth {:.4f}, faceted {:.4f}\n", rs, rf);
  EXPECT_LT(rs, 0.5 * rf);
}

TEST(ShadingNormals, ObjNormalsAreReadAndTransformedByTheInverseTranspose) {
  // One triangle with vn (0, 1, 1)/√2 at every corner, scaled by (2, 1, 1) and mirrored in x by the scene: the
  // normal becomes normalize(M^-T n) = normalize((0, 1, 1)), and the mirror keeps it on the front side.
  const std::string dir = test::tempDir();
  test::writeText(dir + "/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -1\nvn 0 1 1\nf 1//1 2//1 3//1\n");
  for (const char* scale : {"[2, 1, 1]", "[-2, 1, 1]"}) {
    test::writeText(dir + "/scene.json", fmt::format(R"({{
      "camera": {{"position": [0, 0, 3], "look_at": [0, 0, 0]}},
      "materials": {{"m": {{"type": "diffuse", "albedo": 0.5}}}},
      "shapes": [{{"type": "mesh", "material": "m", "file": "tri.obj", "transform": {{"scale": {}}}}}],
      "lights": [{{"type": "point", "position": [0, 2, 2], "power": 1}}]}})", scale));
    const SceneDesc d = loadScene(dir + "/scene.json");
    const ShapeDesc& s = d.shapes.at(0);
    ASSERT_EQ(s.normals.size(), 4u) << scale;
    const Vec3d ng = glm::cross(s.vertices[s.faces[0].v[1]] - s.vertices[s.faces[0].v[0]],
                                s.vertices[s.faces[0].v[2]] - s.vertices[s.faces[0].v[0]]);
    for (int k = 0; k < 3; ++k) {
      test::expectNear(s.cornerNormal(0, k), glm::normalize(Vec3(0, 1, 1)), 1e-5f, scale);
      EXPECT_GT(glm::dot(Vec3d(s.cornerNormal(0, k)), ng), 0.0) << scale;
    }
  }
}

/// scenes/normal-map.json at 32 × 24.
SceneDesc normalMapScene() {
  SceneDesc d = loadScene(test::source("scenes/normal-map.json"));
  d.camera.width = 32, d.camera.height = 24;
  return d;
}

TEST(ShadingNormals, LightTracingAgreesWithPathTracing) {
  // Particles scatter with the adjoint BSDF (Veach's correction); without it the normal-mapped walls differ.
  FIRSTSHOT_STATISTICS_ONLY("ShadingNormals.NormalMapTiltsLambertShadingAsComputed");
  test::expectAgreesWithPathTracing("light", "normal-map", normalMapScene(), 600, 300);
}

TEST(ShadingNormals, BdptAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("ShadingNormals.NormalMapTiltsLambertShadingAsComputed");
  test::expectAgreesWithPathTracing("bdpt", "normal-map", normalMapScene(), 200, 300);
}

/// The first-shot table of scenes/normal-map.json (default settings), made once.
const FirstShotTable& normalMapTable() {
  static const FirstShotTable table = test::preprocessDefault(normalMapScene());
  return table;
}

TEST(ShadingNormals, FirstShotAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("ShadingNormals.NormalMapTiltsLambertShadingAsComputed");
  const SceneDesc desc = normalMapScene();
  const test::BiasMeasure m = test::firstShotImageBias(desc, normalMapTable(), 64);
  fmt::print("normal-map: first-shot − NEE = {:+.3f}% ± {:.3f}%\n", 100 * m.relative(), 100 * m.relativeSe());
  EXPECT_LT(std::abs(m.relative()), std::max(3 * m.relativeSe(), 0.003));
}

TEST(ShadingNormals, ImagesIdenticalForOneAndTwoThreads) {
  const SceneDesc desc = normalMapScene();
  const RenderScene fs(desc, normalMapTable());
  test::expectSameImageForOneAndTwoThreads(fs);
}

}  // namespace
