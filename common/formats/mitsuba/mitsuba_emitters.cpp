// Mitsuba emitters outside shapes → lights, sky and environment (mitsuba_emitters.h).
#include "common/formats/mitsuba/mitsuba_emitters.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/formats/mitsuba/mitsuba_daylight.h"
#include "common/lights/photometry.h"
#include "common/lights/sky_models.h"
#include "common/lights/spot_cone.h"
#include "common/lights/sun_position.h"
#include "common/scene/sky_desc.h"

namespace firstshot::mitsuba {

namespace {

/// A name for the emitter: its path, and its id if it has one.
std::string emitterName(const Document& doc, pugi::xml_node node) {
  const std::string p = doc.path(node);
  return node.attribute("id") ? p + " (\"" + node.attribute("id").value() + "\")" : p;
}

/// @throws InputError unless @p m keeps +y up (a rotation about y, possibly scaled, not mirrored): firstshot's skies
/// and environment maps are y-up. Returns the angle (degrees) by which it turns +z towards +x about y.
double rotationAboutY(const Document& doc, pugi::xml_node node, const Mat4d& m) {
  const Vec3d up(m * glm::dvec4(0, 1, 0, 0)), front(m * glm::dvec4(0, 0, 1, 0));
  const bool upright = glm::length(up) > 0 && glm::length(front) > 0 &&
                       glm::normalize(up).y > 1.0 - 1e-9 && std::abs(glm::normalize(front).y) < 1e-6;
  if (!upright || glm::determinant(glm::dmat3(m)) <= 0)
    doc.fail(node, "to_world must keep +y up (a rotation about y): firstshot's skies and environment maps are y-up");
  return glm::degrees(std::atan2(front.x, front.z));
}

/// The moment of Mitsuba's latitude/longitude/time keys (its defaults: Tokyo, 2010-07-10 15:00, UTC+9).
CivilTime civilTime(Plugin& p) {
  CivilTime t;
  t.year = p.integer("year", 2010), t.month = p.integer("month", 7), t.day = p.integer("day", 10);
  t.utcOffsetHours = p.number("timezone", 9.0);
  const double seconds = p.number("hour", 15.0) * 3600.0 + p.number("minute", 0.0) * 60.0 + p.number("second", 0.0);
  if (!(seconds >= 0 && seconds < 86400.0)) p.doc().fail(p.node(), "hour, minute and second must give a time of day");
  t.hour = int(seconds / 3600.0);
  t.minute = int((seconds - 3600.0 * t.hour) / 60.0);
  t.second = std::min(seconds - 3600.0 * t.hour - 60.0 * t.minute, std::nextafter(60.0, 0.0));
  std::string why;
  if (!isValidCivilTime(t, &why)) p.doc().fail(p.node(), "no such moment (" + why + ")");
  return t;
}

/// `sunsky`, `sky` and `sun`: Mitsuba 0.6's Hošek–Wilkie sky and Preetham sun, as a Preetham sky and a directional
/// sun of the same mean brightness (docs/scene-format.md lists each difference).
void daylight(Document& doc, Plugin& p, SceneDesc& scene, const std::string& name) {
  const std::string& t = p.type();
  const bool withSky = t != "sun", withSun = t != "sky";
  const Mat4d m = p.transform("to_world");
  rotationAboutY(doc, p.node(), m);
  const double scale = p.number("scale", 1.0);
  const double skyScale = t == "sunsky" ? p.number("sky_scale", scale) : scale;
  const double sunScale = t == "sunsky" ? p.number("sun_scale", scale) : scale;
  if (!(skyScale >= 0 && sunScale >= 0)) doc.fail(p.node(), "scale, sky_scale and sun_scale must not be negative");
  const double turbidity = p.number("turbidity", 3.0);
  if (!(turbidity >= 1 && turbidity <= 10)) doc.fail(p.take("turbidity"), "turbidity must be in [1, 10]");
  Vec3d toSun;
  if (p.has("sun_direction")) {
    for (const char* k : {"latitude", "longitude", "timezone", "year", "month", "day", "hour", "minute", "second"})
      if (p.has(k)) doc.fail(p.take(k), "give either sun_direction or the place and time, not both");
    toSun = p.point("sun_direction", Vec3d(0, 1, 0));  // world space, as Mitsuba takes it
    if (!(glm::length(toSun) > 0)) doc.fail(p.take("sun_direction"), "sun_direction is zero");
  } else {
    const double lat = p.number("latitude", 35.6894), lon = p.number("longitude", 139.6917);
    if (std::abs(lat) > 90 || std::abs(lon) > 360) doc.fail(p.node(), "latitude or longitude out of range");
    // Mitsuba's sun position (Blanco-Muriel et al. 2001) has no refraction: Meeus' without it agrees within 0.05°.
    const SunPosition pos = sunPosition(civilTime(p), lat, lon, Atmosphere{0.0, 10.0});
    toSun = Vec3d(m * glm::dvec4(sunDirection(pos, Vec3d(0, 0, -1)), 0));  // north −z, east +x, as Mitsuba's
  }
  toSun = glm::normalize(toSun);
  if (!(toSun.y > 0))
    doc.fail(p.node(), "the sun is below the horizon (altitude " + std::to_string(glm::degrees(std::asin(toSun.y))) +
                           "°): the sky model has no night sky");
  const double elevationDeg = glm::degrees(std::asin(std::min(toSun.y, 1.0)));
  const Color albedo = p.color("albedo", Color(0.2f));
  if (glm::any(glm::greaterThan(glm::abs(albedo - Color(0.2f)), Color(1e-6f))))
    doc.note("sky albedo", "sky albedo: the sky's brightness is Mitsuba's at its default ground albedo 0.2 (at "
                           "turbidity 3, 25°: 8% brighter than at albedo 0, 23% darker than at 1)");
  if (p.number("stretch", 1.0) != 1.0 || p.boolean("extend", false))
    doc.note("sky stretch", "sky stretch and extend ignored: the sky ends at the horizon, black below, as Mitsuba's "
                            "default");
  p.integer("resolution", 512);  // Mitsuba's baking resolution; the renderer bakes the sky at its own
  const double radiusScale = p.number("sun_radius_scale", 1.0);
  if (!(radiusScale >= 0)) doc.fail(p.take("sun_radius_scale"), "sun_radius_scale must not be negative");

  const Color sunIrradiance =
      withSun ? sunRadiance(turbidity, std::acos(toSun.y)) * float(sunSolidAngle() * sunScale) : Color(0.0f);
  if (withSky) {
    if (scene.sky || scene.environment) doc.fail(p.node(), "a scene has one sky or environment emitter");
    auto sky = std::make_shared<SkyDesc>();
    double abcde[5];
    preethamCoefficients(turbidity, abcde);
    sky->turbidity = turbidity;
    sky->groundReflectance = 0.0;  // Mitsuba's sky is black below the horizon
    // Mitsuba's Y_h in its RGB scale, read as W/m² per channel like its <rgb> values; the dome's lux are K times it.
    const double lux = photometry::kEfficacy * skyScale * skyHorizontalLuminance(turbidity, elevationDeg);
    sky->dome = SkyLuminance::perez(toSun, abcde, lux);
    sky->sunHorizontalLux = photometry::lux(sunIrradiance) * toSun.y;
    scene.sky = std::move(sky);
    doc.note("sky", t + ": Mitsuba's Hošek–Wilkie sky approximated by the Preetham distribution of the same turbidity "
                        "and sun, scaled to Mitsuba's horizontal illuminance (within 4%), achromatic (Mitsuba's is "
                        "bluish)");
  }
  if (withSun && maxComponent(sunIrradiance) > 0.0f) {
    LightDesc l;
    l.name = name + " sun";
    l.type = LightType::Directional;
    l.direction = -toSun;
    l.irradiance = sunIrradiance;
    scene.lights.push_back(l);
    if (radiusScale != 0.0)
      doc.note("sun disk", "the sun is a directional light (sharp shadows) with the irradiance of Mitsuba's disk of "
                           "0.27° × sun_radius_scale radius");
  }
}

/// `envmap` and `constant` → the scene's environment.
void environment(Document& doc, Plugin& p, SceneDesc& scene, const FileResolver& resolve) {
  if (scene.sky || scene.environment) doc.fail(p.node(), "a scene has one sky or environment emitter");
  auto env = std::make_shared<EnvironmentDesc>();
  if (p.type() == "constant") {
    env->constant = p.color("radiance", Color(1.0f));
  } else {
    const std::string name = p.string("filename", "");
    if (name.empty()) doc.fail(p.node(), "missing <string name=\"filename\">");
    env->file = resolve(name).string();
    if (!std::filesystem::is_regular_file(env->file))
      doc.fail(p.take("filename"), "cannot open the environment map \"" + env->file + "\"");
    env->scale = float(p.number("scale", 1.0));
    if (!(env->scale >= 0)) doc.fail(p.take("scale"), "scale must not be negative");
    // Mitsuba looks up column atan2(x, −z)/2π of the direction in its local frame: its left edge is seen along −z,
    // where firstshot's map has its centre; so the map turns by to_world's angle about y plus 180°.
    double r = rotationAboutY(doc, p.node(), p.transform("to_world")) + 180.0;
    env->rotateDeg = r > 180.0 ? r - 360.0 : r;
    if (p.has("gamma")) doc.note("envmap gamma", "envmap gamma ignored: float images are linear, 8-bit ones decoded as "
                                                 "value/255 (docs/scene-format.md, environment)");
    p.number("gamma", 1.0);
  }
  scene.environment = std::move(env);
}

}  // namespace

void readEmitter(Document& doc, pugi::xml_node node, SceneDesc& scene, const FileResolver& resolve) {
  Plugin p(doc, node);
  const std::string& t = p.type();
  if (t == "sunsky" || t == "sky" || t == "sun") {
    daylight(doc, p, scene, emitterName(doc, node));
    p.finish();
    return;
  }
  if (t == "envmap" || t == "constant") {
    environment(doc, p, scene, resolve);
    p.finish();
    return;
  }
  LightDesc l;
  l.name = emitterName(doc, node);
  const Mat4d m = p.transform("to_world");
  const Vec3d origin(m * glm::dvec4(0, 0, 0, 1)), axis(m * glm::dvec4(0, 0, 1, 0));
  if (t == "point") {
    l.type = LightType::Point;
    l.position = p.point("position", origin);
    l.power = p.color("intensity", Color(1.0f)) * float(4 * kPi);  // W/sr → W
  } else if (t == "spot") {
    l.type = LightType::Spot;
    l.position = origin;
    l.direction = axis;
    l.outerAngleDeg = p.number("cutoff_angle", 20.0);
    l.innerAngleDeg = std::min(p.number("beam_width", 0.75 * l.outerAngleDeg), l.outerAngleDeg);
    if (!(l.outerAngleDeg > 0 && l.outerAngleDeg <= 180 && l.innerAngleDeg > 0))
      doc.fail(node, "cutoff_angle and beam_width must be in (0, 180] degrees");
    l.power = p.color("intensity", Color(1.0f)) * float(SpotCone(l).integral());  // on-axis W/sr → W
    doc.note("spot", "spot falloff: Mitsuba's linear ramp in angle from beam_width to cutoff_angle approximated by "
                     "a smoothstep in cos(angle) over the same cone (same on-axis intensity)");
  } else if (t == "directional") {
    l.type = LightType::Directional;
    l.direction = p.point("direction", axis);
    l.irradiance = p.color("irradiance", Color(1.0f));
  } else if (t == "area") {
    doc.fail(node, "an area emitter belongs inside a <shape>");
  } else {
    doc.fail(node, "emitter type \"" + t + "\" is not supported (point, spot, directional, sunsky, sky, sun, envmap, "
                   "constant; area inside a shape)");
  }
  p.finish();
  scene.lights.push_back(l);
}

}  // namespace firstshot::mitsuba
