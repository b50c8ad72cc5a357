// Mitsuba's daylight and environment emitters (common/formats/mitsuba/mitsuba_emitters.cpp): sunsky against the JSON Preetham sky
// with the same parameters (the same SceneDesc), the sky's and the sun's brightness at scale 1 against values measured
// from Mitsuba 0.6's own model, its sun position, envmap's lat-long convention against Mitsuba's lookup formula, the
// constant environment, and the errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <glm/gtc/matrix_transform.hpp>

#include "common/formats/load_scene.h"
#include "common/formats/mitsuba/mitsuba_daylight.h"
#include "common/lights/photometry.h"
#include "common/scene/sky_desc.h"
#include "common/util/error.h"
#include "render/output/image_io.h"
#include "render/scene/environment_map.h"
#include "render/scene/sky_light.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;

namespace {

std::string writeScene(const std::string& name, const std::string& text) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/" + name, text);
  return dir + "/" + name;
}

SceneDesc xml(const std::string& body, const std::string& version = "0.6.0") {
  return loadScene(writeScene("scene.xml", "<scene version=\"" + version + "\">\n" + body + "\n</scene>\n"));
}

const char* kFloor = R"(<shape type="rectangle"><transform name="toWorld"><rotate x="1" angle="-90"/></transform></shape>)";

/// The classroom's sunsky: turbidity 3, the sun along this direction, the sky ×6 and the sun ×10.
const Vec3d kClassroomSun = glm::normalize(Vec3d(-0.865804, 0.416766, -0.276929));

}  // namespace

TEST(MitsubaDaylight, SunskyIsTheJsonPreethamSky) {
  const SceneDesc x = xml(std::string(kFloor) + R"(
    <emitter type="sunsky">
      <float name="turbidity" value="3"/>
      <vector name="sunDirection" x="-0.865804" y="0.416766" z="-0.276929"/>
      <float name="skyScale" value="6"/> <float name="sunScale" value="10"/> <float name="sunRadiusScale" value="18.8"/>
    </emitter>)");
  const double elevation = glm::degrees(std::asin(kClassroomSun.y));
  const double lux = photometry::kEfficacy * 6 * mitsuba::skyHorizontalLuminance(3, elevation);
  const Color sun = mitsuba::sunRadiance(3, std::acos(kClassroomSun.y)) * float(10 * mitsuba::sunSolidAngle());
  const std::string dir = test::tempDir();
  test::writeText(dir + "/s.json", fmt::format(R"({{
    "shapes": [{{"type": "quad", "vertices": [[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]], "material": "m"}}],
    "materials": {{"m": {{"type": "diffuse", "albedo": 0.5}}}},
    "sky": {{"type": "preetham", "turbidity": 3, "horizontal_illuminance": {:.17g}, "ground_reflectance": 0,
            "sun": {{"direction": [{:.17g}, {:.17g}, {:.17g}], "irradiance": [{:.9g}, {:.9g}, {:.9g}]}}}}}})",
                                                  lux, -kClassroomSun.x, -kClassroomSun.y, -kClassroomSun.z, sun.x,
                                                  sun.y, sun.z));
  const SceneDesc j = loadScene(dir + "/s.json");
  ASSERT_TRUE(x.sky && j.sky);
  EXPECT_EQ(x.sky->dome.type(), j.sky->dome.type());
  EXPECT_EQ(x.sky->turbidity, j.sky->turbidity);
  EXPECT_EQ(x.sky->groundReflectance, 0.0);
  EXPECT_NEAR(x.sky->dome.horizontalIlluminance(), j.sky->dome.horizontalIlluminance(), 1e-9 * lux);
  EXPECT_NEAR(x.sky->dome.zenithLuminance(), j.sky->dome.zenithLuminance(), 1e-9 * lux);
  EXPECT_NEAR(x.sky->sunHorizontalLux, j.sky->sunHorizontalLux, 1e-5 * j.sky->sunHorizontalLux);
  for (const Vec3d d : {Vec3d(0, 1, 0), Vec3d(1, 0.1, 0), Vec3d(-0.3, 0.5, 0.8), kClassroomSun})
    EXPECT_NEAR(x.sky->dome.luminance(glm::normalize(d)), j.sky->dome.luminance(glm::normalize(d)), 1e-9 * lux);
  ASSERT_EQ(x.lights.size(), 1u);
  ASSERT_EQ(j.lights.size(), 1u);
  EXPECT_EQ(x.lights[0].type, LightType::Directional);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(x.lights[0].direction[c], j.lights[0].direction[c], 1e-9);
    EXPECT_NEAR(x.lights[0].irradiance[c], j.lights[0].irradiance[c], 1e-6 * j.lights[0].irradiance[c]);
  }
}

// Mitsuba 0.6 at scale 1 (its sky: the Hošek–Wilkie RGB model / 106.856980, integrated over the upper hemisphere;
// its sun: Preetham's attenuated solar spectrum through the CIE observer, times the 0.5358° disk's solid angle),
// measured from Mitsuba's sources for these cases.
TEST(MitsubaDaylight, BrightnessAtScaleOneIsMitsubas) {
  struct Case {
    double turbidity, elevationDeg, skyY;
    Color sun;
  };
  const double classroom = glm::degrees(std::asin(kClassroomSun.y));
  for (const Case& c : {Case{3, classroom, 0.18947, Color(1.02207f, 0.776927f, 0.532285f)},
                        Case{5, 10, 0.15754, Color(0.177156f, 0.0829722f, 0.0218026f)},
                        Case{5, 45, 0.33097, Color(1.04253f, 0.809539f, 0.5985f)},
                        Case{5, 70, 0.35731, Color(1.20763f, 0.977758f, 0.783982f)}}) {
    const std::string w = fmt::format("turbidity {}, {:.2f}°", c.turbidity, c.elevationDeg);
    EXPECT_NEAR(mitsuba::skyHorizontalLuminance(c.turbidity, c.elevationDeg), c.skyY, 0.015 * c.skyY) << w;
    const Color sun = mitsuba::sunRadiance(c.turbidity, glm::radians(90 - c.elevationDeg)) *
                      float(mitsuba::sunSolidAngle());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(sun[k], c.sun[k], 0.005 * c.sun[k] + 1e-4) << w << " channel " << k;
  }
}

TEST(MitsubaDaylight, SunPositionIsMitsubas) {
  // Mitsuba's defaults: Tokyo (35.6894 N, 139.6917 E, UTC+9), 2010-07-10 15:00. Its own algorithm (Blanco-Muriel et
  // al. 2001, no refraction) puts the sun at zenith 43.9207°, azimuth 265.7523°: direction (−0.691757, 0.720300,
  // 0.051378) in its frame (north −z, east +x).
  const SceneDesc x = xml(std::string(kFloor) + R"(<emitter type="sun"/>)");
  ASSERT_EQ(x.lights.size(), 1u);
  const Vec3d toSun = -glm::normalize(x.lights[0].direction);
  EXPECT_FALSE(x.sky) << "the sun alone has no sky";
  EXPECT_LT(glm::degrees(std::acos(glm::dot(toSun, Vec3d(-0.691757, 0.720300, 0.051378)))), 0.05);
  // The same moment given explicitly, a rotation about y turning the frame by 90°: the sun turns with it.
  const SceneDesc r = xml(std::string(kFloor) + R"(<emitter type="sunsky"><integer name="year" value="2010"/>
      <transform name="toWorld"><rotate y="1" angle="90"/></transform></emitter>)");
  ASSERT_EQ(r.lights.size(), 1u);
  const Vec3d turned = -glm::normalize(r.lights[0].direction);
  EXPECT_NEAR(turned.x, toSun.z, 1e-6);
  EXPECT_NEAR(turned.z, -toSun.x, 1e-6);
}

TEST(MitsubaDaylight, ErrorsNameTheElement) {
  auto expectError = [](const std::string& body, const std::string& what) {
    try {
      xml(std::string(kFloor) + body);
      ADD_FAILURE() << "accepted: " << body;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("scene/emitter")) << e.what();
      EXPECT_THAT(e.what(), HasSubstr(what)) << e.what();
    }
  };
  expectError(R"(<emitter type="sunsky"><vector name="sunDirection" x="0" y="-1" z="0"/></emitter>)", "below the horizon");
  expectError(R"(<emitter type="sky"><transform name="toWorld"><rotate x="1" angle="90"/></transform></emitter>)",
              "+y up");
  expectError(R"(<emitter type="sunsky"><vector name="sunDirection" x="0" y="1" z="0"/><float name="latitude" value="3"/>
                 </emitter>)", "not both");
  expectError(R"(<emitter type="sky"><float name="turbidity" value="11"/></emitter>)", "turbidity");
  expectError(R"(<emitter type="sky"/><emitter type="constant"/>)", "one sky or environment");
  expectError(R"(<emitter type="envmap"><string name="filename" value="missing.exr"/></emitter>)", "cannot open");
}

TEST(MitsubaDaylight, EnvmapFollowsMitsubasLatLongConvention) {
  // A 16 × 8 map, every texel its own colour, turned by to_world (a rotation of 30° about y) and scaled by 2.
  const int w = 16, h = 8;
  std::vector<float> px(size_t(w * h * 3));
  for (int k = 0; k < w * h; ++k) px[size_t(3 * k)] = float(k + 1), px[size_t(3 * k + 1)] = 1, px[size_t(3 * k + 2)] = 0.5f;
  const std::string dir = test::tempDir();
  image::writeExr(dir + "/env.exr", w, h, {"R", "G", "B"}, px.data());
  test::writeText(dir + "/s.xml", std::string("<scene version=\"3.0.0\">") + kFloor + R"(
    <emitter type="envmap"><string name="filename" value="env.exr"/><float name="scale" value="2"/>
      <transform name="to_world"><rotate y="1" angle="30"/></transform></emitter></scene>)");
  const SceneDesc x = loadScene(dir + "/s.xml");
  ASSERT_TRUE(x.environment);
  EXPECT_EQ(x.environment->scale, 2.0f);
  const auto map = makeInfiniteLight(x);
  ASSERT_TRUE(map);
  const Mat4d toWorld = glm::rotate(Mat4d(1.0), glm::radians(30.0), Vec3d(0, 1, 0)), toLocal = glm::inverse(toWorld);
  int checked = 0;
  for (int a = 0; a < 40; ++a)
    for (int b = 1; b < 20; ++b) {
      const double phi = 2 * kPi * (a + 0.37) / 40, theta = kPi * (b + 0.21) / 20;
      const Vec3d d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      // Mitsuba's lookup: v = to_world⁻¹ d, u = atan2(v.x, −v.z)/2π wrapped into [0, 1), v = acos(v.y)/π.
      const Vec3d v(toLocal * glm::dvec4(d, 0));
      double u = std::atan2(v.x, -v.z) / (2 * kPi);
      u -= std::floor(u);
      const int i = std::min(int(u * w), w - 1), j = std::min(int(std::acos(v.y) / kPi * h), h - 1);
      const float expected = 2.0f * px[size_t(3 * (j * w + i))];
      const float got = map->radiance(Vec3(d)).x;
      // Directions within 10⁻³ of a texel border may round either way in float.
      const double row = std::acos(v.y) / kPi * h;
      const double du = std::abs(u * w - std::round(u * w)), dv = std::abs(row - std::round(row));
      if (du < 1e-3 || dv < 1e-3) continue;
      EXPECT_EQ(got, expected) << "direction " << d.x << ", " << d.y << ", " << d.z;
      ++checked;
    }
  EXPECT_GT(checked, 700);
  // The JSON environment that is the same: the file, the scale, and Mitsuba's angle plus 180°.
  test::writeText(dir + "/s.json", R"({"shapes": [{"type": "quad", "vertices": [[-1, 0, 1], [1, 0, 1], [1, 0, -1],
      [-1, 0, -1]], "material": "m"}], "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
      "environment": {"file": "env.exr", "scale": 2, "rotate": -150}})");
  const SceneDesc j = loadScene(dir + "/s.json");
  EXPECT_EQ(std::filesystem::path(x.environment->file), std::filesystem::path(j.environment->file));
  EXPECT_NEAR(x.environment->rotateDeg, j.environment->rotateDeg, 1e-9);
}

TEST(MitsubaDaylight, ConstantIsAUniformEnvironment) {
  const SceneDesc x = xml(std::string(kFloor) + R"(<emitter type="constant"><rgb name="radiance" value="0.5, 1, 2"/></emitter>)");
  ASSERT_TRUE(x.environment);
  EXPECT_TRUE(x.environment->file.empty());
  const auto map = makeInfiniteLight(x);
  for (const Vec3 d : {Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0.6f, 0, 0.8f)}) {
    const Color c = map->radiance(d);
    EXPECT_EQ(c, Color(0.5f, 1.0f, 2.0f));
  }
  Vec3 d;
  float pdf = 0;
  const Color c = map->sample(Vec2(0.3f, 0.7f), d, pdf);
  EXPECT_EQ(c, Color(0.5f, 1.0f, 2.0f));
  EXPECT_NEAR(pdf, map->pdf(d), 1e-5f * pdf);
}
