// The JSON scene format's daylight keys: "sky", "sun" and "environment" (scene_sky.h, docs/scene-format.md).
#include "common/formats/json/scene_sky.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "common/lights/perez_sky.h"
#include "common/lights/photometry.h"
#include "common/lights/sun_position.h"
#include "common/scene/sky_desc.h"

namespace firstshot {

namespace {

constexpr double kSunDegree = kPi / 180.0;

/// The sun of a "sun" block: where it stands and, if given, its irradiance.
struct SunInput {
  bool given = false;
  std::string where;            ///< its JSON path ("sun" or "sky.sun"), also the light's name
  Vec3d toSun{0.0, 1.0, 0.0};   ///< unit, towards the sun (y up)
  int dayOfYear = 172;          ///< from its date (Perez's extraterrestrial irradiance); 172 for a direction
  bool hasIrradiance = false;
  Color irradiance{0.0f};       ///< on a plane facing the sun, W/m² (the renderer's units)
};

/// Day of the year (1–366) of @p t's civil date.
int sunDayOfYear(const CivilTime& t) {
  CivilTime noon = t, first = t;
  noon.hour = first.hour = 12;
  noon.minute = first.minute = 0;
  noon.second = first.second = 0.0;
  noon.utcOffsetHours = first.utcOffsetHours = 0.0;
  first.month = first.day = 1;
  return int(std::lround(julianDay(noon) - julianDay(first))) + 1;
}

/// The moment of a "sun" block: "date" YYYY-MM-DD, "time" HH:MM or HH:MM:SS (civil time), "timezone" (hours from
/// UTC).
CivilTime sunCivilTime(const SceneJsonReader& r, const Json& j, const std::string& where) {
  CivilTime t;
  char tail = 0;
  const std::string date = r.string(r.need(j, where, "date"), where + ".date");
  if (std::sscanf(date.c_str(), "%d-%d-%d%c", &t.year, &t.month, &t.day, &tail) != 3)
    r.fail(where + ".date", "expected \"YYYY-MM-DD\" (got \"" + date + "\")");
  const std::string time = r.string(r.need(j, where, "time"), where + ".time");
  const int fields = std::sscanf(time.c_str(), "%d:%d:%lf%c", &t.hour, &t.minute, &t.second, &tail);
  if (fields != 2 && fields != 3) r.fail(where + ".time", "expected \"HH:MM\" or \"HH:MM:SS\" (got \"" + time + "\")");
  t.utcOffsetHours = r.number(r.need(j, where, "timezone"), where + ".timezone");
  std::string why;
  if (!isValidCivilTime(t, &why)) {
    auto starts = [&](const char* word) { return why.rfind(word, 0) == 0; };
    const char* key = starts("UTC")                                        ? ".timezone"
                      : starts("year") || starts("month") || starts("day") ? ".date"
                                                                           : ".time";
    r.fail(where + key, "no such moment (" + why + ")");
  }
  return t;
}

SunInput parseSun(const SceneJsonReader& r, const Json& j, const std::string& where) {
  r.keys(j, where, {"direction", "latitude", "longitude", "timezone", "date", "time", "north_angle", "irradiance",
                    "illuminance"});
  SunInput s;
  s.given = true;
  s.where = where;
  const bool placed = j.contains("latitude") || j.contains("longitude") || j.contains("timezone") ||
                      j.contains("date") || j.contains("time") || j.contains("north_angle");
  if (j.contains("direction") == placed)
    r.fail(where, "give either \"direction\" or \"latitude\", \"longitude\", \"timezone\", \"date\" and \"time\"");
  if (j.contains("direction")) {
    const Vec3d d = r.vec3(j["direction"], where + ".direction");
    if (!(glm::length(d) > 0)) r.fail(where + ".direction", "direction is zero");
    s.toSun = -glm::normalize(d);
  } else {
    const double lat = r.number(r.need(j, where, "latitude"), where + ".latitude");
    if (std::abs(lat) > 90) r.fail(where + ".latitude", "must be in [-90, 90] degrees");
    const double lon = r.number(r.need(j, where, "longitude"), where + ".longitude");
    if (std::abs(lon) > 180) r.fail(where + ".longitude", "must be in [-180, 180] degrees (east positive)");
    const CivilTime t = sunCivilTime(r, j, where);
    const double a = j.contains("north_angle") ? r.number(j["north_angle"], where + ".north_angle") * kSunDegree : 0.0;
    s.toSun = sunDirection(sunPosition(t, lat, lon), Vec3d(std::sin(a), 0.0, -std::cos(a)));
    s.dayOfYear = sunDayOfYear(t);
  }
  if (!(s.toSun.y > 0.0)) {
    char msg[96];
    std::snprintf(msg, sizeof msg, "the sun is below the horizon (altitude %.2f degrees)",
                  std::asin(std::clamp(s.toSun.y, -1.0, 1.0)) / kSunDegree);
    r.fail(where, msg);
  }
  if (j.contains("irradiance") && j.contains("illuminance"))
    r.fail(where, "give only one of \"irradiance\" (W/m²) and \"illuminance\" (lux)");
  if (j.contains("irradiance")) s.irradiance = r.color(j["irradiance"], where + ".irradiance");
  if (j.contains("illuminance"))
    s.irradiance = Color(skyRadiance(r.nonNegative(j["illuminance"], where + ".illuminance")));  // lux → W/m², white
  s.hasIrradiance = j.contains("irradiance") || j.contains("illuminance");
  return s;
}

/// "sky": the dome's model and scale, and (Perez) the sun's irradiance from the model's direct part.
void parseSky(const SceneJsonReader& r, const Json& j, SunInput& sun, SceneDesc& scene) {
  const std::string where = "sky";
  r.keys(j, where, {"type", "horizontal_illuminance", "zenith_luminance", "direct_normal_irradiance",
                    "diffuse_horizontal_irradiance", "ground_reflectance", "turbidity", "sun"});
  const std::string type = r.string(r.need(j, where, "type"), where + ".type");
  if (j.contains("sun")) sun = parseSun(r, j["sun"], where + ".sun");
  auto sky = std::make_shared<SkyDesc>();
  if (j.contains("ground_reflectance")) {
    sky->groundReflectance = r.nonNegative(j["ground_reflectance"], where + ".ground_reflectance");
    if (sky->groundReflectance > 1) r.fail(where + ".ground_reflectance", "must be in [0, 1]");
  }
  auto only = [&](std::initializer_list<const char*> keys, const char* why) {
    for (const char* k : keys)
      if (j.contains(k)) r.fail(where + "." + k, why);
  };
  if (type != "preetham") only({"turbidity"}, "goes with \"type\": \"preetham\"");
  if (type == "cie-overcast" || type == "cie-clear" || type == "preetham") {
    only({"direct_normal_irradiance", "diffuse_horizontal_irradiance"}, "goes with \"type\": \"perez\"");
    const bool overcast = type == "cie-overcast";
    if (!overcast && !sun.given) r.fail(where, "a " + type + " sky needs a \"sun\" (its position shapes the sky)");
    if (!overcast && !sun.hasIrradiance)
      r.fail(sun.where, "missing key \"irradiance\" (or \"illuminance\"): the " + type +
                            " sky has no direct part of its own");
    if (j.contains("horizontal_illuminance") == j.contains("zenith_luminance"))
      r.fail(where, "give one of \"horizontal_illuminance\" (lux) and \"zenith_luminance\" (cd/m²)");
    double abcde[5] = {0, 0, 0, 0, 0};
    if (type == "preetham") {
      sky->turbidity = j.contains("turbidity") ? r.number(j["turbidity"], where + ".turbidity") : 3.0;
      if (!(sky->turbidity >= 1 && sky->turbidity <= 10)) r.fail(where + ".turbidity", "must be in [1, 10]");
      preethamCoefficients(sky->turbidity, abcde);
    }
    auto make = [&](double lux) {
      return overcast            ? SkyLuminance::overcast(lux)
             : type == "cie-clear" ? SkyLuminance::clear(sun.toSun, lux)
                                   : SkyLuminance::perez(sun.toSun, abcde, lux);
    };
    if (j.contains("horizontal_illuminance")) {
      sky->dome = make(r.positive(j["horizontal_illuminance"], where + ".horizontal_illuminance"));
    } else {  // the model at 1 lux has zenith luminance Lz1: Lz lux / Lz1 gives Lz
      const double lz = r.positive(j["zenith_luminance"], where + ".zenith_luminance");
      sky->dome = make(lz / make(1.0).zenithLuminance());
    }
  } else if (type == "perez") {
    only({"horizontal_illuminance", "zenith_luminance"}, "a Perez sky is scaled by \"diffuse_horizontal_irradiance\"");
    if (!sun.given) r.fail(where, "a Perez sky needs a \"sun\"");
    if (sun.hasIrradiance)
      r.fail(sun.where, "a Perez sky's sun gets its irradiance from \"direct_normal_irradiance\": leave it out here");
    PerezInput& in = sky->perez;
    in.directNormal = r.nonNegative(r.need(j, where, "direct_normal_irradiance"), where + ".direct_normal_irradiance");
    in.diffuseHorizontal =
        r.positive(r.need(j, where, "diffuse_horizontal_irradiance"), where + ".diffuse_horizontal_irradiance");
    in.dayOfYear = sun.dayOfYear;
    try {
      const PerezSky p = makePerezSky(sun.toSun, in);
      sky->dome = p.dome;
      sun.irradiance = Color(skyRadiance(p.directNormalLux));  // In · direct efficacy, lux → W/m² at kEfficacy
      sun.hasIrradiance = true;
    } catch (const std::invalid_argument& e) {
      r.fail(where, e.what());
    }
  } else {
    r.fail(where + ".type", "unknown sky type \"" + type + "\" (cie-overcast, cie-clear, perez, preetham)");
  }
  if (sun.given && sun.hasIrradiance) sky->sunHorizontalLux = photometry::lux(sun.irradiance) * sun.toSun.y;
  scene.sky = std::move(sky);
}

void parseEnvironment(const SceneJsonReader& r, const Json& j, SceneDesc& scene) {
  const std::string where = "environment";
  r.keys(j, where, {"file", "scale", "rotate"});
  auto env = std::make_shared<EnvironmentDesc>();
  std::filesystem::path p(r.string(r.need(j, where, "file"), where + ".file"));
  if (p.is_relative()) p = std::filesystem::path(r.file()).parent_path() / p;
  if (!std::filesystem::is_regular_file(p))
    r.fail(where + ".file", "cannot open the environment map \"" + p.string() + "\"");
  env->file = p.string();
  if (j.contains("scale")) env->scale = float(r.nonNegative(j["scale"], where + ".scale"));
  if (j.contains("rotate")) env->rotateDeg = r.number(j["rotate"], where + ".rotate");
  scene.environment = std::move(env);
}

}  // namespace

void parseDaylight(const SceneJsonReader& r, const Json& root, SceneDesc& scene) {
  SunInput sun;
  if (root.contains("sun")) sun = parseSun(r, root["sun"], "sun");
  if (root.contains("sky")) {
    if (sun.given && root["sky"].is_object() && root["sky"].contains("sun"))
      r.fail("sky.sun", "the sun is given twice (\"sun\" and \"sky.sun\")");
    parseSky(r, root["sky"], sun, scene);
  }
  if (sun.given) {
    if (!sun.hasIrradiance) r.fail(sun.where, "missing key \"irradiance\" (or \"illuminance\")");
    if (maxComponent(sun.irradiance) > 0.0f) {  // a directional light: first-shot replaces it (a small light)
      LightDesc l;
      l.name = sun.where;
      l.type = LightType::Directional;
      l.direction = -sun.toSun;
      l.irradiance = sun.irradiance;
      scene.lights.push_back(l);
    }
  }
  if (root.contains("environment")) {
    if (scene.sky) r.fail("environment", "a scene has a \"sky\" or an \"environment\", not both");
    parseEnvironment(r, root["environment"], scene);
  }
}

}  // namespace firstshot
