// Mitsuba 0.6's and 3's bsdfs without a model of their own here (common/formats/mitsuba/mitsuba_bsdf.cpp, mitsuba_bsdf_mix.cpp,
// mitsuba_lobes.cpp): roughdiffuse's albedo against a Monte Carlo estimate of Oren–Nayar's white-sky albedo (3σ);
// ward's albedo against its closed form; phong, ward, coating, roughcoating, blendbsdf and mask against the JSON
// materials their documented mappings give, value by value; each approximation noted once; errors with their line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <random>

#include "common/formats/load_scene.h"
#include "common/formats/mitsuba/mitsuba_lobes.h"
#include "common/materials/texture.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "render/output/image_io.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;

namespace {

/// A fresh folder with quad.obj (a unit quad with texture coordinates) and w.png (a 2 × 1 grey image, 51 and 204).
struct Folder {
  std::string dir = test::tempDir();
  Folder() {
    test::writeText(dir + "/quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
    const uint8_t grey[6] = {51, 51, 51, 204, 204, 204};
    image::writePng(dir + "/w.png", 2, 1, grey);
  }
  /// The materials of the XML scene of one quad per bsdf in @p bsdfs, in order.
  std::vector<MaterialDesc> xml(std::initializer_list<std::string> bsdfs, const char* version = "3.0.0") const {
    std::string body;
    for (const std::string& b : bsdfs) body += R"(<shape type="obj"><string name="filename" value="quad.obj"/>)" + b + "</shape>\n";
    test::writeText(dir + "/scene.xml", fmt::format("<scene version=\"{}\">\n{}</scene>\n", version, body));
    return materialsOf(loadScene(dir + "/scene.xml"));
  }
  /// The materials of the JSON scene of one quad per material in @p materials (JSON objects), in order.
  std::vector<MaterialDesc> json(std::initializer_list<std::string> materials) const {
    std::string m, s;
    int k = 0;
    for (const std::string& x : materials) {
      m += fmt::format("{}\"m{}\": {}", k ? ", " : "", k, x);
      s += fmt::format(R"({}{{"type": "mesh", "file": "quad.obj", "material": "m{}"}})", k ? ", " : "", k);
      ++k;
    }
    test::writeText(dir + "/scene.json", R"({"materials": {)" + m + R"(}, "shapes": [)" + s +
                                             R"(], "lights": [{"type": "point", "position": [0, 0, 1], "power": 1}]})");
    return materialsOf(loadScene(dir + "/scene.json"));
  }
  static std::vector<MaterialDesc> materialsOf(const SceneDesc& s) {
    std::vector<MaterialDesc> out;
    for (const ShapeDesc& shape : s.shapes) out.push_back(s.materials.at(shape.material));
    return out;
  }
};

void expectNear(const Color& a, const Color& b, const std::string& what, double tol = 1e-6) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << what << " channel " << c;
}

/// The same material: type, every parameter, the alpha keys, and textures by their lookups at a few points.
void expectSame(const MaterialDesc& a, const MaterialDesc& b, const std::string& what) {
  EXPECT_EQ(a.type, b.type) << what;
  expectNear(a.albedo, b.albedo, what + " albedo");
  expectNear(a.specular, b.specular, what + " specular");
  expectNear(a.transmittance, b.transmittance, what + " transmittance");
  EXPECT_NEAR(a.exponent, b.exponent, 1e-5 * std::max(1.0f, b.exponent)) << what;
  EXPECT_NEAR(a.ior, b.ior, 1e-6) << what;
  EXPECT_NEAR(a.metallic, b.metallic, 1e-6) << what;
  EXPECT_NEAR(a.roughness, b.roughness, 1e-6) << what;
  EXPECT_EQ(a.alphaMode, b.alphaMode) << what;
  EXPECT_NEAR(a.alpha, b.alpha, 1e-6) << what;
  ASSERT_EQ(bool(a.albedoTexture), bool(b.albedoTexture)) << what;
  ASSERT_EQ(bool(a.alphaTexture), bool(b.alphaTexture)) << what;
  for (float u : {0.1f, 0.3f, 0.6f, 0.9f, 1.4f}) {
    const Vec2 uv(u, 0.5f);
    if (a.albedoTexture) expectNear(a.albedoTexture->lookup(uv), b.albedoTexture->lookup(uv), what + " albedo texture", 2e-6);
    if (a.alphaTexture) {
      EXPECT_NEAR(a.alphaTexture->alphaLookup(uv), b.alphaTexture->alphaLookup(uv), 2e-6) << what << " alpha at " << u;
    }
  }
}

void expectSame(const std::vector<MaterialDesc>& x, const std::vector<MaterialDesc>& j) {
  ASSERT_EQ(x.size(), j.size());
  for (size_t k = 0; k < x.size(); ++k) expectSame(x[k], j[k], "material " + std::to_string(k));
}

size_t count(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t p = text.find(part); p != std::string::npos; p = text.find(part, p + 1)) ++n;
  return n;
}

/// π × Oren and Nayar's BRDF (1994, with the interreflection term) for reflectance ρ and σ, at polar angles
/// @p ti, @p to and azimuth difference @p dphi, written from the paper.
double orenNayarPi(double rho, double sigma, double ti, double to, double dphi) {
  const double s2 = sigma * sigma, a = std::max(ti, to), b = std::min(ti, to), c = std::cos(dphi);
  const double c1 = 1 - 0.5 * s2 / (s2 + 0.33);
  const double c2 = 0.45 * s2 / (s2 + 0.09) * (c >= 0 ? std::sin(a) : std::sin(a) - std::pow(2 * b / kPi, 3));
  const double c3 = 0.125 * s2 / (s2 + 0.09) * std::pow(4 * a * b / (kPi * kPi), 2);
  const double l1 = rho * (c1 + c * c2 * std::tan(b) + (1 - std::abs(c)) * c3 * std::tan((a + b) / 2));
  const double l2 = 0.17 * rho * rho * s2 / (s2 + 0.13) * (1 - c * std::pow(2 * b / kPi, 2));
  return l1 + l2;
}

}  // namespace

TEST(MitsubaBsdfs, RoughDiffuseHasOrenNayarsWhiteSkyAlbedo) {
  // The white-sky albedo (1/π)∫∫ f cosθi cosθo dωi dωo is the mean of π f over cosine-distributed directions in and
  // out: a Monte Carlo estimate with its σ, against the material's albedo (the quadrature of common/formats/mitsuba/mitsuba_lobes.h).
  const Folder f;
  const double alpha = 0.45, sigma = alpha / std::sqrt(2.0);
  const Color rho(0.2f, 0.5f, 0.9f);
  const auto x = f.xml({fmt::format(R"(<bsdf type="roughdiffuse"><rgb name="reflectance" value="0.2, 0.5, 0.9"/>
                                       <float name="alpha" value="{}"/></bsdf>)", alpha),
                        R"(<bsdf type="roughdiffuse"><float name="alpha" value="0"/></bsdf>)"});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 200000;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const double ti = std::asin(std::sqrt(u(rng))), to = std::asin(std::sqrt(u(rng))), dphi = 2 * kPi * u(rng);
    for (int c = 0; c < 3; ++c) {
      const double v = orenNayarPi(rho[c], sigma, ti, to, dphi);
      sum[c] += v, sum2[c] += v * v;
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / n, se = std::sqrt((sum2[c] / n - mean * mean) / (n - 1));
    fmt::print("roughdiffuse channel {}: albedo {:.5f}, Monte Carlo {:.5f} ± {:.5f}\n", c, x[0].albedo[c], mean, se);
    EXPECT_NEAR(x[0].albedo[c], mean, 3 * se) << "channel " << c << ": σ " << se;
    EXPECT_LT(x[0].albedo[c], rho[c]) << "rough: darker than Lambert of the same reflectance";
  }
  expectNear(x[1].albedo, Color(0.5f), "alpha 0: Lambert");
  // Without roughness the quadrature is exact; the fast approximation has no interreflection term.
  const mitsuba::OrenNayarAlbedo smooth = mitsuba::orenNayarAlbedo(0.0, false), fast = mitsuba::orenNayarAlbedo(alpha, true);
  EXPECT_NEAR(smooth.single, 1.0, 1e-12);
  EXPECT_EQ(smooth.twice, 0.0);
  EXPECT_EQ(fast.twice, 0.0);
}

TEST(MitsubaBsdfs, WardAlbedoAtNormalIncidence) {
  // The balanced variant at normal incidence in closed form: with x = tan²(θ/2), 2π ∫ f cosθ sinθ dθ becomes
  // (1/α²) ∫₀¹ (1 − x) e^(−x/α²) dx = 1 − α²(1 − e^(−1/α²)).
  for (double alpha : {0.05, 0.1, 0.2, 0.4, 0.7}) {
    EXPECT_NEAR(mitsuba::wardAlbedoAtNormalIncidence(alpha, "balanced"), 1 - alpha * alpha * (1 - std::exp(-1 / (alpha * alpha))), 1e-5)
        << alpha;
    // Ward's and Dür's normalisations lose more at grazing exitance.
    EXPECT_LT(mitsuba::wardAlbedoAtNormalIncidence(alpha, "ward"), mitsuba::wardAlbedoAtNormalIncidence(alpha, "ward-duer"));
  }
  EXPECT_NEAR(mitsuba::phongExponentOfRoughness(0.1), 49.5, 1e-12);
  EXPECT_EQ(mitsuba::phongExponentOfRoughness(1.5), 0.0);
}

TEST(MitsubaBsdfs, PhongAndWardMatchJson) {
  // Glossy: albedo = diffuse_reflectance; specular = the lobe's albedo at normal incidence × (n + 2)/(n + 1).
  const Folder f;
  const double a = 0.2, n = (2 / (a * a) - 2) / 4, wardAlbedo = 1 - a * a * (1 - std::exp(-1 / (a * a)));
  testing::internal::CaptureStderr();
  const auto x = f.xml({R"(<bsdf type="phong"><float name="exponent" value="20"/><rgb name="specularReflectance" value="0.3"/>
                             <rgb name="diffuseReflectance" value="0.4, 0.3, 0.2"/></bsdf>)",
                        R"(<bsdf type="phong"><rgb name="diffuseReflectance" value="0.8"/><rgb name="specularReflectance" value="0.4"/></bsdf>)",
                        R"(<bsdf type="ward"><float name="alphaU" value="0.2"/><float name="alphaV" value="0.2"/>
                             <rgb name="specularReflectance" value="0.25, 0.2, 0.15"/></bsdf>)",
                        R"(<bsdf type="ward"><string name="variant" value="ward"/><float name="alpha" value="0.2"/></bsdf>)"},
                       "0.6.0");
  const std::string err = testing::internal::GetCapturedStderr();
  const double ward = mitsuba::wardAlbedoAtNormalIncidence(a, "ward");
  // The second phong: 0.8 + 0.4 > 1, both scaled by 1/1.2 as Mitsuba does; the lobe then lowered to 1 − albedo.
  const auto j = f.json({fmt::format(R"({{"type": "glossy", "albedo": [0.4, 0.3, 0.2], "specular": {}, "exponent": 20}})", 0.3 * 22 / 21),
                         R"({"type": "glossy", "albedo": 0.6666666, "specular": 0.3333333, "exponent": 30})",
                         fmt::format(R"({{"type": "glossy", "albedo": 0.5, "specular": [{}, {}, {}], "exponent": {}}})", 0.25 * wardAlbedo * (n + 2) / (n + 1),
                                     0.2 * wardAlbedo * (n + 2) / (n + 1), 0.15 * wardAlbedo * (n + 2) / (n + 1), n),
                         fmt::format(R"({{"type": "glossy", "albedo": 0.5, "specular": {}, "exponent": {}}})", 0.2 * ward * (n + 2) / (n + 1), n)});
  expectSame(x, j);
  EXPECT_EQ(count(err, "phong mapped to glossy"), 1u) << err;
  EXPECT_EQ(count(err, "ward mapped to glossy"), 1u) << err;
}

// Every mapping case spells out its XML, its JSON and the notes it expects (as test_mitsuba_bitmap.cpp): data, not logic.
TEST(MitsubaBsdfs, CoatingMatchesJson) {
  // Over a diffuse bsdf: pbr of metallic 0, ior int_ior/ext_ior, roughness √α, base = reflectance × e^(−2 σa d).
  // Over another bsdf: that bsdf, its colours tinted by the same absorption (noted).
  const Folder f;
  testing::internal::CaptureStderr();
  const auto x = f.xml({R"(<bsdf type="coating"><float name="intIOR" value="1.6"/><float name="extIOR" value="1"/>
                             <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.4, 0.3"/></bsdf></bsdf>)",
                        R"(<bsdf type="roughcoating"><float name="alpha" value="0.16"/><rgb name="sigmaA" value="0.1, 0.2, 0.3"/>
                             <float name="thickness" value="2"/><float name="intIOR" value="1.5"/><float name="extIOR" value="1"/>
                             <bsdf type="diffuse"/></bsdf>)",
                        R"(<bsdf type="coating"><rgb name="sigmaA" value="0.5"/>
                             <bsdf type="phong"><rgb name="diffuseReflectance" value="0.5"/><float name="exponent" value="10"/></bsdf></bsdf>)"},
                       "0.6.0");
  const std::string err = testing::internal::GetCapturedStderr();
  const double t = std::exp(-1.0);  // e^(−2 · 0.5 · 1)
  const auto j = f.json({R"({"type": "pbr", "base_color": [0.5, 0.4, 0.3], "metallic": 0, "roughness": 0, "ior": 1.6})",
                         fmt::format(R"({{"type": "pbr", "base_color": [{}, {}, {}], "metallic": 0, "roughness": 0.4, "ior": 1.5}})",
                                     0.5 * std::exp(-0.4), 0.5 * std::exp(-0.8), 0.5 * std::exp(-1.2)),
                         fmt::format(R"({{"type": "glossy", "albedo": {}, "specular": {}, "exponent": 10}})", 0.5 * t, 0.2 * 12 / 11 * t)});
  expectSame(x, j);
  EXPECT_EQ(count(err, "xml: coating over a diffuse bsdf mapped"), 1u) << err;
  EXPECT_EQ(count(err, "xml: roughcoating over a diffuse bsdf mapped"), 1u) << err;
  EXPECT_EQ(count(err, "xml: coating over a bsdf other than diffuse"), 1u) << err;
}

TEST(MitsubaBsdfs, BlendMatchesJson) {
  const Folder f;
  testing::internal::CaptureStderr();
  const std::string d2 = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.2"/></bsdf>)";
  const std::string d8 = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.6, 0.4"/></bsdf>)";
  const auto x = f.xml({
      // Exact: two diffuse bsdfs (weight 0.25: ¾ of the first); a diffuse and a glossy one (phong).
      R"(<bsdf type="blendbsdf"><float name="weight" value="0.25"/>)" + d2 + d8 + "</bsdf>",
      R"(<bsdf type="blendbsdf"><float name="weight" value="0.5"/><bsdf type="diffuse"><rgb name="reflectance" value="0.3"/></bsdf>
           <bsdf type="phong"><rgb name="diffuse_reflectance" value="0.1"/><rgb name="specular_reflectance" value="0.4"/>
           <float name="exponent" value="10"/></bsdf></bsdf>)",
      // Exact: a bitmap weight (raw: 0.2 | 0.8) between two diffuse colours, baked into a texture.
      R"(<bsdf type="blendbsdf"><texture type="bitmap" name="weight"><string name="filename" value="w.png"/>
           <boolean name="raw" value="true"/><string name="filter_type" value="nearest"/></texture>)" + d2 + d8 + "</bsdf>",
      // The weights at the ends: one bsdf or the other.
      R"(<bsdf type="blendbsdf"><float name="weight" value="0"/>)" + d2 + d8 + "</bsdf>",
      R"(<bsdf type="blendbsdf"><float name="weight" value="1"/>)" + d2 + d8 + "</bsdf>",
      // Approximated: diffuse with a plastic (pbr): base blended, the coat's F0 scaled by the plastic's weight.
      R"(<bsdf type="blendbsdf"><float name="weight" value="0.75"/><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>
           <bsdf type="roughplastic"><float name="alpha" value="0.09"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/>
           <rgb name="diffuse_reflectance" value="0.2"/></bsdf></bsdf>)",
      // Approximated: glass with a diffuse bsdf: the heavier one.
      R"(<bsdf type="blendbsdf"><float name="weight" value="0.3"/><bsdf type="dielectric"/>)" + d2 + "</bsdf>",
      // Exact: a textured diffuse bsdf with a phong one: the blend baked into the texels, and the factor 1 − specular
      // leaving room for the lobe (the texels divided by it).
      R"(<bsdf type="blendbsdf"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="w.png"/>
           <boolean name="raw" value="true"/></texture></bsdf>
           <bsdf type="phong"><rgb name="diffuse_reflectance" value="0.1"/><float name="exponent" value="10"/></bsdf></bsdf>)"});
  const std::string err = testing::internal::GetCapturedStderr();
  // The weight texture's values are its stored bytes (raw) 51/255 and 204/255.
  const double w0 = 51 / 255.0, w1 = 204 / 255.0;
  std::vector<float> texels;
  for (const double w : {w0, w1})
    for (const double c : {0.8, 0.6, 0.4}) texels.push_back(float(0.2 * (1 - w) + c * w));
  image::writeExr(f.dir + "/blend.exr", 2, 1, {"R", "G", "B"}, texels.data());
  const double s = 0.5 * 0.2 * 12 / 11;  // half of phong's lobe (specular_reflectance 0.2)
  std::vector<float> glossy;
  for (const double w : {w0, w1})
    for (int c = 0; c < 3; ++c) glossy.push_back(float((0.5 * w + 0.5 * 0.1) / (1 - s)));
  image::writeExr(f.dir + "/glossy.exr", 2, 1, {"R", "G", "B"}, glossy.data());
  const double f0 = 0.04 * 0.75, r = std::sqrt(f0);
  const auto j = f.json({R"({"type": "diffuse", "albedo": [0.35, 0.3, 0.25]})",
                         fmt::format(R"({{"type": "glossy", "albedo": 0.2, "specular": {}, "exponent": 10}})", 0.5 * 0.4 * 12 / 11),
                         R"({"type": "diffuse", "albedo_texture": {"file": "blend.exr", "filter": "nearest"}})",
                         R"({"type": "diffuse", "albedo": 0.2})", R"({"type": "diffuse", "albedo": [0.8, 0.6, 0.4]})",
                         fmt::format(R"({{"type": "pbr", "base_color": 0.3, "metallic": 0, "roughness": 0.3, "ior": {}}})", (1 + r) / (1 - r)),
                         R"({"type": "dielectric", "ior": 1.504183})",
                         fmt::format(R"({{"type": "glossy", "albedo": {:.9f}, "specular": {:.9f}, "exponent": 10,
                                          "albedo_texture": "glossy.exr"}})", 1 - s - 1e-9, s)});
  expectSame(x, j);
  EXPECT_EQ(count(err, "blendbsdf of a diffuse and a pbr-like bsdf"), 1u) << err;
  EXPECT_EQ(count(err, "the one of larger weight is used"), 1u) << err;
}

TEST(MitsubaBsdfs, MaskIsABlendCutOut) {
  // Mitsuba's mask lets a ray through with probability 1 − opacity: the JSON's blend cut-out of alpha = opacity; a
  // bitmap opacity (raw here, its grey bytes 0.2 | 0.8) is the alpha texture.
  const Folder f;
  testing::internal::CaptureStderr();
  const auto x = f.xml({R"(<bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="diffuse"/></bsdf>)",
                        R"(<bsdf type="twosided"><bsdf type="mask"><texture type="bitmap" name="opacity"><string name="filename" value="w.png"/>
                             <boolean name="raw" value="true"/></texture><bsdf type="roughplastic"/></bsdf></bsdf>)",
                        R"(<bsdf type="mask"><float name="opacity" value="0.5"/><bsdf type="mask"><float name="opacity" value="0.5"/>
                             <bsdf type="diffuse"/></bsdf></bsdf>)",
                        R"(<bsdf type="mask"><spectrum name="opacity" value="1"/><bsdf type="diffuse"/></bsdf>)",
                        R"(<bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="dielectric"/></bsdf>)"});
  const std::string err = testing::internal::GetCapturedStderr();
  const auto j = f.json({R"({"type": "diffuse", "albedo": 0.5, "alpha_mode": "blend", "alpha": 0.3})",
                         fmt::format(R"({{"type": "pbr", "base_color": 0.5, "metallic": 0, "roughness": {}, "ior": {},
                                          "alpha_mode": "blend", "alpha_texture": "w.png"}})", std::sqrt(0.1), 1.49 / 1.000277),
                         R"({"type": "diffuse", "albedo": 0.5, "alpha_mode": "blend", "alpha": 0.25})",
                         R"({"type": "diffuse", "albedo": 0.5})",
                         R"({"type": "dielectric", "ior": 1.504183})"});
  expectSame(x, j);
  EXPECT_EQ(count(err, "mask over a glass or mirror bsdf"), 1u) << err;
  // An area emitter under a mask stays opaque (an emitting surface cannot be a cut-out), noted.
  test::writeText(f.dir + "/lamp.xml", R"(<scene version="3.0.0"><shape type="rectangle">
      <bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="diffuse"/></bsdf>
      <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape></scene>)");
  testing::internal::CaptureStderr();
  const SceneDesc lamp = loadScene(f.dir + "/lamp.xml");
  EXPECT_THAT(testing::internal::GetCapturedStderr(), HasSubstr("a masked area emitter is opaque"));
  EXPECT_FALSE(lamp.materials[lamp.shapes[0].material].isCutout());
}

TEST(MitsubaBsdfs, BadBsdfsAreNamed) {
  const Folder f;
  const std::pair<std::string, const char*> cases[] = {
      {R"(<bsdf type="blendbsdf"><bsdf type="diffuse"/></bsdf>)", "blendbsdf needs two nested <bsdf> (it has 1)"},
      {R"(<bsdf type="mask"><float name="opacity" value="0.5"/></bsdf>)", "mask needs one nested <bsdf>"},
      {R"(<bsdf type="coating"><bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf>)", "coating needs one nested <bsdf>"},
      {R"(<bsdf type="ward"><string name="variant" value="ashikhmin"/></bsdf>)", "unknown ward variant \"ashikhmin\""},
      {R"(<bsdf type="phong"><float name="exponent" value="-1"/></bsdf>)", "must not be negative"}};
  for (const auto& [bsdf, message] : cases) {
    SCOPED_TRACE(message);
    test::writeText(f.dir + "/bad.xml", "<scene version=\"3.0.0\">\n<shape type=\"cube\">\n" + bsdf + "\n</shape></scene>\n");
    try {
      loadScene(f.dir + "/bad.xml");
      ADD_FAILURE() << "not refused";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("bad.xml: scene/shape/bsdf"));
      EXPECT_THAT(e.what(), HasSubstr("(line 3)"));
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  }
}
