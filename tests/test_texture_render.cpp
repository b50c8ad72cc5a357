// Textured surfaces in the renderer: a textured plane under a point light shows texel × E/π (NEE and
// first-shot), first-shot agrees with NEE on a textured Cornell box, diffuse or pbr with a metallic-roughness texture (patch
// NEE included), a metallic-roughness texture sets the lobe per point, and the image does not
// depend on the thread count.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/materials/texture.h"
#include "tests/bias_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// A 4 × 4 checker of two linear values @p odd and @p even, one texel per square.
std::shared_ptr<const Texture> checkerOf(const Color& odd, const Color& even, const char* name) {
  std::vector<Color> texels(16);
  for (int i = 0; i < 16; ++i) texels[size_t(i)] = (i % 4 + i / 4) % 2 ? odd : even;
  auto t = std::make_shared<Texture>();
  t->image = std::make_shared<const TexelImage>(makeTexelImage(4, 4, std::move(texels), name));
  return t;
}

/// A base-colour checker of two colours.
std::shared_ptr<const Texture> checker() { return checkerOf(Color(0.9f, 0.3f, 0.1f), Color(0.1f, 0.4f, 0.8f), "checker"); }

/// The plane y = 0 (2 m × 2 m, its texture's v[0] corner at (−1, 0, −1)) seen from 3 m above under a point light.
SceneDesc texturedPlane(double patchSize) {
  SceneDesc s = test::sceneFromJson(fmt::format(R"({{
    "camera": {{"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30, "resolution": [32, 32]}},
    "materials": {{"floor": {{"type": "diffuse", "albedo": 1}}}},
    "shapes": [{{"type": "quad", "material": "floor", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}}],
    "lights": [{{"type": "point", "position": [0.2, 1, 0.1], "power": 100}}],
    "settings": {{"patch_size": {}}}}})", patchSize));
  s.materials[0].albedoTexture = checker();
  return s;
}

/// Expected channel @p c of every pixel: the footprint average of texel(x) × E(x)/π.
std::vector<double> expectedImage(const SceneDesc& desc, int c) {
  const Camera camera(desc.camera);
  const Texture& t = *desc.materials[0].albedoTexture;
  const Vec3d light = desc.lights[0].position;
  std::vector<double> e(size_t(camera.width()) * camera.height());
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x)
      e[size_t(y) * camera.width() + x] = test::footprintAverage(camera, x, y, [&](const Ray& r) {
        const Vec3d p = Vec3d(r.o) - double(r.o.y) / double(r.d.y) * Vec3d(r.d);
        const Vec3d d = light - p;
        const double E = 100.0 / (4 * kPi) * d.y / std::pow(glm::dot(d, d), 1.5);
        const Vec2 uv((p.z + 1) / 2, (1 - p.x) / 2);  // the quad's natural coordinates
        return double(t.lookup(uv)[c]) * E / kPi;
      }, 16);
  return e;
}

void expectTexelTimesIrradiance(const SceneDesc& desc, const Film& film, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    const test::Comparison r = test::compareImage(film, expectedImage(desc, c), c, 8, 2e-4);
    fmt::print("{} channel {}: diff {:+.2e} ± {:.2e} of {:.4f}, worst block z {:.2f}\n", what, c, r.meanDiff, r.se,
               r.meanExpected, r.worstBlockZ);
    EXPECT_LE(std::abs(r.meanDiff), 3 * r.se + 2e-4) << what << " channel " << c;
    EXPECT_LE(r.worstBlockZ, 4.0) << what << " channel " << c;
  }
}

TEST(TextureRender, PointLightOnATexturedPlaneShowsTexelTimesIrradiance) {
  IntegratorOptions io;
  io.maxDepth = 1;
  const SceneDesc desc = texturedPlane(0.1);
  const RenderScene nee(desc);
  expectTexelTimesIrradiance(desc, test::renderPath(nee, io, 16).film, "NEE");
  // First-shot at the camera hit (exact factors): the texel there, not the patch's mean.
  io.primary = PrimaryMode::Patch;
  const RenderScene fs(desc, test::pointLightTable(desc, buildPatches(desc, 0.1), 0));
  expectTexelTimesIrradiance(desc, test::renderPath(fs, io, 16).film, "first-shot");
}

/// A 4 × 4 metallic-roughness checker (glTF layout: roughness in G, metallic in B): a rough dielectric
/// (roughness 1, metallic 0) and a glossy metal (roughness 0.5, metallic 1), one texel per square.
std::shared_ptr<const Texture> mrChecker() {
  return checkerOf(Color(0.0f, 0.5f, 1.0f), Color(0.0f, 1.0f, 0.0f), "mr-checker");
}

TEST(TextureRender, MetallicRoughnessTextureSetsTheLobeAtEachPoint) {
  // A pbr plane (base colour 0.8, factors metallic 1, roughness 1) with the metallic-roughness checker, under a
  // point light: each pixel shows f(uv) · I cosθ/d², f the BSDF of the factors × the texel at the point, seen
  // through NEE and through first-shot at the camera hit (exact factors). The same BSDF per point: bsdfAt.
  SceneDesc desc = texturedPlane(0.1);
  MaterialDesc& m = desc.materials[0];
  m.type = MaterialType::Pbr, m.albedo = Color(0.8f), m.metallic = 1.0f, m.roughness = 1.0f, m.ior = 1.5f;
  m.albedoTexture = nullptr;
  m.metallicRoughnessTexture = mrChecker();
  const Camera camera(desc.camera);
  const Vec3d light = desc.lights[0].position;
  const Vec3 eye(desc.camera.position);
  std::vector<std::vector<double>> expected(3, std::vector<double>(size_t(camera.width()) * camera.height()));
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x)
        expected[size_t(c)][size_t(y) * camera.width() + x] = test::footprintAverage(camera, x, y, [&](const Ray& r) {
          const Vec3d p = Vec3d(r.o) - double(r.o.y) / double(r.d.y) * Vec3d(r.d);
          const Vec3d d = light - p;
          const double dist = std::sqrt(glm::dot(d, d));
          const Color mr = m.metallicRoughnessTexture->lookup(Vec2((p.z + 1) / 2, (1 - p.x) / 2));
          const BSDF f = makeBSDF(m, m.albedo, mr.z, mr.y);
          const Vec3 wi = Vec3(d / dist), wo = glm::normalize(eye - Vec3(p));  // local frame = world, n = +y
          const BSDFQuery q(Vec3(wi.x, wi.z, wi.y), Vec3(wo.x, wo.z, wo.y));
          return double(f.eval(q)[c]) * 100.0 / (4 * kPi) * (d.y / dist) / (dist * dist);
        }, 16);
  IntegratorOptions io;
  io.maxDepth = 1;
  const RenderScene nee(desc);
  io.primary = PrimaryMode::Exact;
  const Film neeFilm = test::renderPath(nee, io, 16).film;
  io.primary = PrimaryMode::Patch;
  const RenderScene fs(desc, test::pointLightTable(desc, buildPatches(desc, 0.1), 0));
  const Film fsFilm = test::renderPath(fs, io, 16).film;
  for (const auto& [film, what] : {std::pair<const Film*, const char*>{&neeFilm, "NEE"}, {&fsFilm, "first-shot"}})
    for (int c = 0; c < 3; ++c) {
      const test::Comparison r = test::compareImage(*film, expected[size_t(c)], c, 8, 2e-4);
      fmt::print("{} channel {}: diff {:+.2e} ± {:.2e} of {:.4f}, worst block z {:.2f}\n", what, c, r.meanDiff, r.se,
                 r.meanExpected, r.worstBlockZ);
      EXPECT_LE(std::abs(r.meanDiff), 3 * r.se + 2e-4) << what << " channel " << c;
      EXPECT_LE(r.worstBlockZ, 4.0) << what << " channel " << c;
    }
}

/// The metre Cornell box with the checker on every diffuse material (its albedo the factor), 32 × 32; with
/// @p pbr they become pbr materials (factors metallic 1, roughness 1) with the metallic-roughness checker too.
SceneDesc texturedCornell(bool pbr = false) {
  SceneDesc desc = test::cornellMetre();
  desc.camera.width = desc.camera.height = 32;
  for (MaterialDesc& m : desc.materials)
    if (m.type == MaterialType::Diffuse && !m.isEmissive()) {
      m.albedoTexture = checker();
      if (!pbr) continue;
      m.type = MaterialType::Pbr, m.metallic = 1.0f, m.roughness = 1.0f;
      m.metallicRoughnessTexture = mrChecker();
    }
  return desc;
}

/// The first-shot table of texturedCornell(@p pbr), made once.
const FirstShotTable& cornellTable(bool pbr = false) {
  static const FirstShotTable table = test::preprocessDefault(texturedCornell()),
                              pbrTable = test::preprocessDefault(texturedCornell(true));
  return pbr ? pbrTable : table;
}

class TexturedCornell : public testing::TestWithParam<bool> {};

TEST_P(TexturedCornell, FirstShotAgreesWithNee) {
  const SceneDesc desc = texturedCornell(GetParam());
  const RenderScene nee(desc, desc.settings.patchSize), fs(desc, cornellTable(GetParam()));
  for (PatchNee patchNee : {PatchNee::Off, PatchNee::Every}) {
    IntegratorOptions io;
    io.maxDepth = 3;
    io.lightSampler = LightStrategy::All;  // pairing: both integrators draw the same random numbers
    auto b = makeIntegrator("path", io);
    io.patchNee = patchNee;
    auto a = makeIntegrator("path", io);
    a->preprocess(fs);
    b->preprocess(nee);
    const test::BiasMeasure m = test::measurePairedBias(*a, *b, nee, Camera(desc.camera), 64, 11);
    fmt::print("patch NEE {}: first-shot − NEE = {:+.3f}% ± {:.3f}%\n", int(patchNee), 100 * m.relative(),
               100 * m.relativeSe());
    EXPECT_LT(std::abs(m.relative()), std::max(3 * m.relativeSe(), 0.003)) << int(patchNee);
  }
}

// Base-colour checkers on diffuse walls, and base-colour and metallic-roughness checkers on pbr walls.
INSTANTIATE_TEST_SUITE_P(TextureRender, TexturedCornell, testing::Values(false, true),
                         [](const testing::TestParamInfo<bool>& i) { return i.param ? "Pbr" : "Diffuse"; });

TEST(TextureRender, ImagesIdenticalForOneAndTwoThreads) {
  const SceneDesc desc = texturedCornell();
  const RenderScene fs(desc, cornellTable());
  IntegratorOptions io;
  io.maxDepth = 3;
  io.patchNee = PatchNee::Every;
  const auto one = test::renderPath(fs, io, 4, 1, 1), two = test::renderPath(fs, io, 4, 1, 2);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ASSERT_EQ(one.film.mean(x, y), two.film.mean(x, y)) << x << ", " << y;
}

}  // namespace
