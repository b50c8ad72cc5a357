// The JSON scene format's daylight keys (common/formats/json/scene_sky.h): the sky's scale by horizontal illuminance or zenith
// luminance, the sun as a directional light from a direction or from place, date and time (Meeus), the Perez sky's
// sun from its direct part, the hash, and bad input naming the key.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/formats/json/scene_json.h"
#include "common/lights/perez_sky.h"
#include "common/lights/photometry.h"
#include "common/lights/sun_position.h"
#include "common/scene/scene_desc.h"
#include "common/scene/sky_desc.h"
#include "common/util/error.h"

using namespace firstshot;

namespace {

/// A plane at y = 0 and the JSON members @p daylight.
std::string planeScene(const std::string& daylight) {
  return fmt::format(R"({{
    "materials": {{"ground": {{"type": "diffuse", "albedo": 0.5}}}},
    "shapes": [{{"type": "quad", "material": "ground", "vertices": [[-5,0,-5],[-5,0,5],[5,0,5],[5,0,-5]]}}],
    {}}})", daylight);
}

SceneDesc parse(const std::string& text) {
  SceneDesc s = parseSceneJson(text, "test.json");
  validateScene(s);
  return s;
}

}  // namespace

TEST(SceneSky, SunFromPlaceAndTimeIsADirectionalLight) {
  const SceneDesc s = parse(planeScene(R"("sun": {"latitude": 39.742476, "longitude": -105.1786, "timezone": -7,
      "date": "2003-10-17", "time": "12:30:30", "north_angle": 90, "illuminance": 50000})"));
  ASSERT_EQ(s.lights.size(), 1u);
  const LightDesc& sun = s.lights[0];
  EXPECT_EQ(sun.name, "sun");
  EXPECT_EQ(sun.type, LightType::Directional);
  EXPECT_FALSE(s.sky);
  // NREL SPA's test case (Reda & Andreas 2004): zenith 50.11°, azimuth 194.34° from north; north here is +x, east +z.
  CivilTime t;
  t.year = 2003, t.month = 10, t.day = 17, t.hour = 12, t.minute = 30, t.second = 30, t.utcOffsetHours = -7;
  const Vec3d expected = sunDirection(sunPosition(t, 39.742476, -105.1786), Vec3d(1, 0, 0));
  EXPECT_NEAR(glm::length(-sun.direction - expected), 0.0, 1e-9);
  EXPECT_NEAR(std::acos(-sun.direction.y) * 180 / kPi, 50.11, 0.02);
  const double az = std::atan2(-sun.direction.z, -sun.direction.x) * 180 / kPi;  // from north (+x) towards east (+z)
  EXPECT_NEAR(az + 360, 194.34, 0.02);
  EXPECT_NEAR(photometry::lux(sun.irradiance), 50000, 0.05);
}

TEST(SceneSky, PerezSunComesFromTheDirectPart) {
  const SceneDesc s = parse(planeScene(R"("sky": {"type": "perez", "direct_normal_irradiance": 600,
      "diffuse_horizontal_irradiance": 100, "ground_reflectance": 0.3, "sun": {"direction": [0.3, -0.8, 0.2]}})"));
  ASSERT_TRUE(s.sky);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].name, "sky.sun");
  const Vec3d toSun = -glm::normalize(Vec3d(0.3, -0.8, 0.2));
  PerezInput in;
  in.directNormal = 600, in.diffuseHorizontal = 100;
  const PerezSky p = makePerezSky(toSun, in);
  EXPECT_NEAR(photometry::lux(s.lights[0].irradiance), p.directNormalLux, 1e-5 * p.directNormalLux);
  EXPECT_NEAR(s.sky->dome.horizontalIlluminance(), p.dome.horizontalIlluminance(), 1e-9 * p.dome.horizontalIlluminance());
  EXPECT_NEAR(s.sky->sunHorizontalLux, p.directNormalLux * toSun.y, 1e-5 * p.directNormalLux);
  EXPECT_NEAR(s.sky->groundLuminance(), 0.3 * (p.dome.horizontalIlluminance() + p.directNormalLux * toSun.y) / kPi,
              1e-5 * s.sky->groundLuminance());
}

TEST(SceneSky, HashOnlyWithDaylight) {
  const std::string plain = planeScene(R"("lights": [])");
  const std::string overcast = planeScene(R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 1000})");
  const std::string brighter = planeScene(R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 2000})");
  EXPECT_NE(hashScene(parse(plain)), hashScene(parse(overcast)));
  EXPECT_NE(hashScene(parse(overcast)), hashScene(parse(brighter)));
  EXPECT_EQ(hashScene(parse(overcast)), hashScene(parse(overcast)));
}

TEST(SceneSky, BadInputNamesTheKey) {
  auto error = [](const std::string& daylight) {
    try {
      parse(planeScene(daylight));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error(R"("sky": {"type": "perez", "direct_normal_irradiance": -5, "diffuse_horizontal_irradiance": 100,
                             "sun": {"direction": [0, -1, 0]}})")
                .find("sky.direct_normal_irradiance"),
            std::string::npos);
  EXPECT_NE(error(R"("sun": {"latitude": 45, "longitude": 7, "timezone": 1, "date": "2026-02-31", "time": "12:00",
                             "irradiance": 1})")
                .find("sun.date"),
            std::string::npos);
  EXPECT_NE(error(R"("environment": {"file": "no-such-map.exr"})").find("environment.file"), std::string::npos);
  EXPECT_NE(error(R"("sky": {"type": "cie-overcast", "horizontal_illuminance": 1000, "zenith_luminance": 300})")
                .find("give one of"),
            std::string::npos);
  EXPECT_NE(error(R"("sun": {"direction": [0, 1, 0], "irradiance": 1})").find("below the horizon"), std::string::npos);
  // The zenith luminance scales the overcast sky: E_h = 7π/9 · Lz.
  const SceneDesc byZenith = parse(planeScene(R"("sky": {"type": "cie-overcast", "zenith_luminance": 3000})"));
  EXPECT_NEAR(byZenith.sky->dome.horizontalIlluminance(), 7 * kPi / 9 * 3000, 1e-6 * 3000);
}

