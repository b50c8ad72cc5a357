// Spectra → linear sRGB (common/color/spectrum_rgb.h) against tabulated colorimetry: flat reflectances are grey, D65 and
// black bodies land on their published chromaticities, the sRGB transfer function; and the Mitsuba reader's
// <spectrum>, <blackbody> and <srgb> values (common/formats/mitsuba/mitsuba_xml.cpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/color/cie_tables.h"
#include "common/color/spectrum_rgb.h"
#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;

namespace {

Vec2d chromaticity(const Vec3d& xyz) { return Vec2d(xyz.x, xyz.y) / (xyz.x + xyz.y + xyz.z); }

Vec2d blackbodyXy(double kelvin) {
  return chromaticity(spectrumXyz([&](double nm) { return planckRadiance(nm, kelvin); }, false));
}

/// The material of the one shape of a Mitsuba scene whose rectangle has @p bsdf, or the emission of @p emitter.
SceneDesc xml(const std::string& body) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/s.xml", "<scene version=\"3.0.0\">" + body + "<emitter type=\"point\"/></scene>");
  return loadScene(dir + "/s.xml");
}

}  // namespace

TEST(SpectrumRgb, FlatReflectanceIsGrey) {
  for (double v : {1.0, 0.5, 0.1}) {
    const Color c = reflectanceRgb(SampledSpectrum{{360, 830}, {v, v}});
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], v, 1e-6 * v) << v;
  }
  // Only part of the band: a long-pass reflectance is reddish, a short-pass one bluish.
  const Color red = reflectanceRgb(SampledSpectrum{{599, 600, 830}, {0, 1, 1}});
  EXPECT_GT(red.x, 0.5f);
  EXPECT_LT(red.z, 0.05f);
}

TEST(SpectrumRgb, ChromaticitiesAreTheTabulatedOnes) {
  // D65 itself: the sRGB white point (0.3127, 0.3290) (CIE 015, table T.3: 0.31272, 0.32903).
  const Vec2d d65 = chromaticity(spectrumXyz([](double nm) {
    const double p = (nm - cie::kFirstNm) / cie::kStepNm;
    const int i = std::min(int(p), cie::kCount - 2);
    return cie::kD65[i] + (p - i) * (cie::kD65[i + 1] - cie::kD65[i]);
  }, false));
  EXPECT_NEAR(d65.x, 0.31272, 2e-4);
  EXPECT_NEAR(d65.y, 0.32903, 2e-4);
  // Planckian radiators (CIE 1931 chromaticities of the Planckian locus): 6500 K (0.3135, 0.3237), 3000 K
  // (0.4369, 0.4041), 2000 K (0.5267, 0.4133).
  const Vec2d t6500 = blackbodyXy(6500), t3000 = blackbodyXy(3000), t2000 = blackbodyXy(2000);
  EXPECT_NEAR(t6500.x, 0.3135, 1e-3);
  EXPECT_NEAR(t6500.y, 0.3237, 1e-3);
  EXPECT_NEAR(t3000.x, 0.4369, 1e-3);
  EXPECT_NEAR(t3000.y, 0.4041, 1e-3);
  EXPECT_NEAR(t2000.x, 0.5267, 1e-3);
  EXPECT_NEAR(t2000.y, 0.4133, 1e-3);
  // D65's correlated colour temperature is 6504 K: the black body there lies within 0.006 of the D65 point (D65 sits
  // 0.003 in Δuv above the locus).
  const Vec2d t6504 = blackbodyXy(6504);
  EXPECT_NEAR(t6504.x, 0.3127, 0.006);
  EXPECT_NEAR(t6504.y, 0.3290, 0.006);
}

TEST(SpectrumRgb, EmissionKeepsMitsubasScale) {
  // A flat spectral radiance of 1 W/(m² sr nm): XYZ = (Σx̄, Σȳ, Σz̄)/Σȳ ≈ (1, 1, 1), the equal-energy white.
  const Color c = emissionRgb([](double) { return 1.0; });
  EXPECT_NEAR(0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z, 1.0, 2e-3);
  EXPECT_NEAR(c.x, 1.2049, 3e-3);
  EXPECT_NEAR(c.y, 0.9484, 3e-3);
  EXPECT_NEAR(c.z, 0.9086, 3e-3);
}

TEST(SpectrumRgb, SrgbTransfer) {
  EXPECT_NEAR(srgbToLinear(0.5), 0.214041, 1e-6);
  EXPECT_NEAR(srgbToLinear(0.04), 0.04 / 12.92, 1e-12);
  EXPECT_NEAR(srgbToLinear(1.0), 1.0, 1e-12);
  EXPECT_NEAR(srgbToLinear(128 / 255.0), 0.2158605, 1e-6);
}

TEST(SpectrumRgb, MitsubaValues) {
  auto albedo = [](const std::string& value) {
    const SceneDesc s = xml("<shape type=\"rectangle\"><bsdf type=\"diffuse\">" + value + "</bsdf></shape>");
    return s.materials[s.shapes[0].material].albedo;
  };
  EXPECT_NEAR(albedo(R"(<spectrum name="reflectance" value="360:0.5, 830:0.5"/>)").y, 0.5, 1e-6);
  EXPECT_NEAR(albedo(R"(<srgb name="reflectance" value="#808080"/>)").x, 0.2158605, 1e-6);
  EXPECT_NEAR(albedo(R"(<srgb name="reflectance" value="0.5, 0.5, 0.5"/>)").z, 0.214041, 1e-6);
  const Color red = albedo(R"(<spectrum name="reflectance" value="400:0, 599:0, 600:1, 830:1"/>)");
  EXPECT_GT(red.x, 5 * red.z);
  auto emission = [](const std::string& value) {
    const SceneDesc s = xml("<shape type=\"rectangle\"><emitter type=\"area\">" + value + "</emitter></shape>");
    return s.materials[s.shapes[0].material].emission;
  };
  const Color flat = emission(R"(<spectrum name="radiance" value="360:2, 830:2"/>)");
  EXPECT_NEAR(flat.x, 2 * 1.2049, 6e-3);
  const Color bb = emission(R"(<spectrum name="radiance" type="blackbody"><float name="temperature" value="3000"/>
      <float name="scale" value="1e-6"/></spectrum>)");
  const Color bb06 = emission(R"(<blackbody name="radiance" temperature="3000K" scale="1e-6"/>)");
  const Color expected = emissionRgb([](double nm) { return planckRadiance(nm, 3000); }) * 1e-6f;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(bb[k], expected[k], 1e-6 * expected[k]);
    EXPECT_NEAR(bb06[k], expected[k], 1e-6 * expected[k]);
  }
  EXPECT_GT(bb.x, bb.z);  // warm
  for (const auto& [bad, why] : std::vector<std::pair<std::string, std::string>>{
           {R"(<spectrum name="reflectance" value="500:0.5, 400:0.5"/>)", "increase"},
           {R"(<spectrum name="reflectance" value="400:x"/>)", "wavelength:value"},
           {R"(<spectrum name="reflectance" type="d65"/>)", "spectrum type"},
           {R"(<srgb name="reflectance" value="#12"/>)", "#rrggbb"}}) {
    try {
      albedo(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(why)) << e.what();
      EXPECT_THAT(e.what(), HasSubstr("line")) << e.what();
    }
  }
}
