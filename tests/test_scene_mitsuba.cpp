// Mitsuba 3 XML scenes (common/formats/mitsuba/scene_mitsuba.cpp): each plugin family against the same scene written
// by hand in the JSON format (docs/scene-format.md), value by value; two families also rendered, the
// image means of the XML and the JSON scene agreeing within 3σ; errors named with element and line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <array>

#include "common/formats/load_scene.h"
#include "common/lights/spot_cone.h"
#include "common/scene/scene_shapes.h"
#include "common/util/error.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;

namespace {

/// Writes @p text as @p name into a fresh folder (with @p extra files beside it) and returns the path.
std::string writeScene(const std::string& name, const std::string& text,
                       const std::vector<std::pair<std::string, std::string>>& extra = {}) {
  const std::string dir = test::tempDir();
  for (const auto& [file, content] : extra) test::writeText(dir + "/" + file, content);
  test::writeText(dir + "/" + name, text);
  return dir + "/" + name;
}

const std::pair<std::string, std::string> kObj = {"tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.5\nf 1 2 3\nf 2 4 3\n"};

/// A Mitsuba scene of @p body, loaded (and validated) through loadScene.
SceneDesc xml(const std::string& body) {
  return loadScene(writeScene("scene.xml", "<scene version=\"3.0.0\">\n" + body + "\n</scene>\n", {kObj}));
}
SceneDesc json(const std::string& text) { return loadScene(writeScene("scene.json", text, {kObj})); }

void expectNear(const Vec3d& a, const Vec3d& b, const std::string& what, double tol = 1e-9) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol * std::max(1.0, std::abs(b[i]))) << what << "[" << i << "]";
}
void expectNear(const Color& a, const Color& b, const std::string& what) { expectNear(Vec3d(a), Vec3d(b), what, 1e-6); }

void expectSameMaterial(const MaterialDesc& a, const MaterialDesc& b) {
  const std::string w = a.name + " vs " + b.name;
  EXPECT_EQ(a.type, b.type) << w;
  expectNear(a.albedo, b.albedo, w + " albedo");
  expectNear(a.specular, b.specular, w + " specular");
  expectNear(a.transmittance, b.transmittance, w + " transmittance");
  expectNear(a.emission, b.emission, w + " emission");
  EXPECT_NEAR(a.exponent, b.exponent, 1e-6 * b.exponent) << w;
  EXPECT_NEAR(a.ior, b.ior, 1e-6) << w;
  EXPECT_NEAR(a.metallic, b.metallic, 1e-6) << w;
  EXPECT_NEAR(a.roughness, b.roughness, 1e-6) << w;
  EXPECT_EQ(a.microfacet, b.microfacet) << w;
  ASSERT_EQ(bool(a.conductor), bool(b.conductor)) << w;
  if (a.conductor) {
    expectNear(a.conductor->eta(), b.conductor->eta(), w + " eta");
    expectNear(a.conductor->k(), b.conductor->k(), w + " k");
  }
}

/// The image's up direction: the camera's up made perpendicular to its view direction.
Vec3d viewUp(const CameraDesc& c) {
  const Vec3d f = glm::normalize(c.lookAt - c.position);
  return glm::normalize(c.up - glm::dot(c.up, f) * f);
}

/// Geometry, materials, lights and camera of two scenes equal within float rounding (names aside).
void expectSameScene(const SceneDesc& x, const SceneDesc& j) {
  ASSERT_EQ(x.shapes.size(), j.shapes.size());
  for (size_t s = 0; s < x.shapes.size(); ++s) {
    const ShapeDesc &a = x.shapes[s], &b = j.shapes[s];
    EXPECT_EQ(a.type, b.type) << a.name;
    ASSERT_EQ(a.vertices.size(), b.vertices.size()) << a.name;
    for (size_t v = 0; v < a.vertices.size(); ++v) expectNear(a.vertices[v], b.vertices[v], a.name + " vertex");
    ASSERT_EQ(a.faces.size(), b.faces.size()) << a.name;
    for (size_t f = 0; f < a.faces.size(); ++f) {
      EXPECT_EQ(a.faces[f].count, b.faces[f].count) << a.name;
      for (int k = 0; k < a.faces[f].count; ++k) EXPECT_EQ(a.faces[f].v[k], b.faces[f].v[k]) << a.name << " face " << f;
    }
    expectSameMaterial(x.materials[a.material], j.materials[b.material]);
  }
  ASSERT_EQ(x.lights.size(), j.lights.size());
  for (size_t i = 0; i < x.lights.size(); ++i) {
    const LightDesc &a = x.lights[i], &b = j.lights[i];
    EXPECT_EQ(a.type, b.type) << a.name;
    EXPECT_EQ(a.shape, b.shape) << a.name;
    expectNear(a.position, b.position, a.name + " position");
    expectNear(a.direction, b.direction, a.name + " direction");
    expectNear(a.power, b.power, a.name + " power");
    expectNear(a.irradiance, b.irradiance, a.name + " irradiance");
    EXPECT_NEAR(a.innerAngleDeg, b.innerAngleDeg, 1e-9) << a.name;
    EXPECT_NEAR(a.outerAngleDeg, b.outerAngleDeg, 1e-9) << a.name;
  }
  expectNear(x.camera.position, j.camera.position, "camera position");
  expectNear(glm::normalize(x.camera.lookAt - x.camera.position), glm::normalize(j.camera.lookAt - j.camera.position),
             "camera direction");
  expectNear(viewUp(x.camera), viewUp(j.camera), "camera up");
  EXPECT_NEAR(x.camera.fovYDeg, j.camera.fovYDeg, 1e-9);
  EXPECT_EQ(x.camera.width, j.camera.width);
  EXPECT_EQ(x.camera.height, j.camera.height);
  EXPECT_EQ(x.settings.spp, j.settings.spp);
  EXPECT_EQ(x.settings.maxDepth, j.settings.maxDepth);
}

const char* kGrey = R"(<bsdf type="twosided" id="grey"><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.4, 0.6"/></bsdf></bsdf>)";

}  // namespace

TEST(MitsubaScene, ShapesMatchJson) {
  const SceneDesc x = xml(std::string(kGrey) + R"(
    <shape type="rectangle">
      <transform name="to_world"><scale x="0.5" y="0.25"/><rotate x="1" angle="-90"/><translate y="2"/></transform>
      <ref id="grey"/>
    </shape>
    <shape type="cube">
      <transform name="to_world"><scale value="0.5"/><translate value="1, 0.5, 0"/></transform>
      <ref id="grey"/>
    </shape>
    <shape type="sphere"><point name="center" x="0" y="1" z="0"/><float name="radius" value="0.3"/><ref id="grey"/></shape>
    <shape type="obj">
      <string name="filename" value="tri.obj"/>
      <boolean name="flip_normals" value="true"/>
      <transform name="to_world"><matrix value="1 0 0 0.5  0 1 0 0  0 0 1 -1  0 0 0 1"/></transform>
      <ref id="grey"/>
    </shape>)");
  const SceneDesc j = json(R"({
    "materials": {"grey": {"type": "diffuse", "albedo": [0.2, 0.4, 0.6]}},
    "shapes": [
      {"type": "quad", "material": "grey", "vertices": [[-0.5, 2, 0.25], [0.5, 2, 0.25], [0.5, 2, -0.25], [-0.5, 2, -0.25]]},
      {"type": "box", "material": "grey", "min": [0.5, 0, -0.5], "max": [1.5, 1, 0.5]},
      {"type": "sphere", "material": "grey", "center": [0, 1, 0], "radius": 0.3, "subdivisions": 3},
      {"type": "mesh", "material": "grey", "file": "tri.obj", "transform": {"translate": [0.5, 0, -1]}, "flip_normals": true}]})");
  expectSameScene(x, j);
  EXPECT_EQ(x.materials[x.shapes[0].material].name, "grey");
}

TEST(MitsubaScene, ZeroAreaFacesAreSkippedAsInJson) {
  const std::string path = writeScene("scene.xml", R"(<scene version="3.0.0"><shape type="obj"><string name="filename" value="flat.obj"/>
      </shape></scene>)", {{"flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"}});
  testing::internal::CaptureStderr();
  const SceneDesc s = loadScene(path);
  EXPECT_THAT(testing::internal::GetCapturedStderr(), HasSubstr("skipped 1 of 2 triangles of"));
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(s.shapes[0].faces.size(), 1u);
}

TEST(MitsubaScene, DiskIsTessellatedWithItsAreaAndNormal) {
  // Mitsuba's disk: the unit disk in z = 0 facing +z; here scaled to radius 0.5 and turned to face +y.
  const SceneDesc s = xml(R"(<shape type="disk">
      <transform name="to_world"><scale value="0.5"/><rotate x="1" angle="-90"/></transform></shape>)");
  ASSERT_EQ(s.shapes.size(), 1u);
  double area = 0;
  for (const Face& f : s.shapes[0].faces) {
    area += shapes::faceArea(s.shapes[0], f);
    const Vec3d n = glm::cross(s.shapes[0].vertices[f.v[1]] - s.shapes[0].vertices[f.v[0]],
                               s.shapes[0].vertices[f.v[2]] - s.shapes[0].vertices[f.v[0]]);
    EXPECT_GT(glm::normalize(n).y, 1 - 1e-9);
  }
  EXPECT_NEAR(area, kPi * 0.25, 1e-9);
  EXPECT_EQ(s.materials[s.shapes[0].material].albedo, Color(0.5f)) << "Mitsuba's default bsdf: diffuse 0.5";
}

TEST(MitsubaScene, BsdfsMatchJson) {
  testing::internal::CaptureStderr();
  const SceneDesc x = xml(R"(
    <bsdf type="diffuse" id="d"><rgb name="reflectance" value="0.1 0.2 0.3"/></bsdf>
    <bsdf type="twosided" id="ts"><bsdf type="diffuse"><spectrum name="reflectance" value="0.7"/></bsdf></bsdf>
    <bsdf type="plastic" id="p">
      <rgb name="diffuse_reflectance" value="0.5, 0.25, 0.125"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/>
    </bsdf>
    <bsdf type="roughplastic" id="rp"><float name="alpha" value="0.2"/><float name="int_ior" value="1.5"/><string name="ext_ior" value="vacuum"/></bsdf>
    <bsdf type="roughplastic" id="rp2"><float name="alpha" value="0.5"/></bsdf>
    <bsdf type="conductor" id="au"><string name="material" value="Au"/></bsdf>
    <bsdf type="principled" id="pr"><rgb name="base_color" value="0.8, 0.4, 0.2"/><float name="metallic" value="0.3"/><float name="roughness" value="0.6"/></bsdf>
    <bsdf type="roughconductor" id="rc"><float name="alpha" value="0.1"/><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.45, 2.14"/></bsdf>
    <bsdf type="dielectric" id="water"><string name="int_ior" value="water"/><string name="ext_ior" value="air"/></bsdf>
    <bsdf type="dielectric" id="glass"><rgb name="specular_transmittance" value="0.9, 0.8, 0.7"/></bsdf>
    <bsdf type="thindielectric" id="thin"/>
    <shape type="rectangle"><ref id="d"/></shape>)");
  const std::string err = testing::internal::GetCapturedStderr();
  // Hand-computed values: plastics are pbr of metallic 0, ior η, roughness √α; conductors carry η and k.
  const double ppEta = 1.49 / 1.000277;  // the default: polypropylene 1.49 over air 1.000277
  // thindielectric: a lossless thin_glass pane of bk7 in air, transmitting (1 − r0)/(1 + r0) at normal incidence.
  const double bk7 = 1.5046 / 1.000277, r0 = (bk7 - 1) * (bk7 - 1) / ((bk7 + 1) * (bk7 + 1));
  const SceneDesc j = json(fmt::format(R"({{
    "materials": {{
      "d": {{"type": "diffuse", "albedo": [0.1, 0.2, 0.3]}},
      "ts": {{"type": "diffuse", "albedo": 0.7}},
      "p": {{"type": "pbr", "base_color": [0.5, 0.25, 0.125], "metallic": 0, "roughness": 0, "ior": 1.5}},
      "rp": {{"type": "pbr", "base_color": 0.5, "metallic": 0, "roughness": {}, "ior": 1.5}},
      "rp2": {{"type": "pbr", "base_color": 0.5, "metallic": 0, "roughness": {}, "ior": {}}},
      "au": {{"type": "mirror", "conductor": "Au"}},
      "pr": {{"type": "pbr", "base_color": [0.8, 0.4, 0.2], "metallic": 0.3, "roughness": 0.6, "ior": 1.5}},
      "rc": {{"type": "pbr", "base_color": 1, "metallic": 1, "roughness": {}, "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.45, 2.14],
              "microfacet": "beckmann"}},
      "water": {{"type": "dielectric", "ior": {}}},
      "glass": {{"type": "dielectric", "ior": {}, "transmittance": [0.9, 0.8, 0.7]}},
      "thin": {{"type": "thin_glass", "ior": {}, "transmittance": {}}}}},
    "shapes": [{{"type": "quad", "material": "d", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}}]}})",
      std::sqrt(0.2), std::sqrt(0.5), ppEta, std::sqrt(0.1), 1.3330 / 1.000277, 1.5046 / 1.000277, bk7, (1 - r0) / (1 + r0)));
  expectSameScene(x, j);
  for (const MaterialDesc& m : j.materials) {
    SCOPED_TRACE(m.name);
    ASSERT_GE(x.findMaterial(m.name), 0);
    expectSameMaterial(x.materials[x.findMaterial(m.name)], m);
  }
  // Each approximation once per bsdf type, one line each.
  for (const char* type : {"xml: roughplastic mapped", "xml: roughconductor mapped"}) {
    size_t count = 0;
    for (size_t pos = err.find(type); pos != std::string::npos; pos = err.find(type, pos + 1)) ++count;
    EXPECT_EQ(count, 1u) << type << " in:\n" << err;
  }
  EXPECT_THAT(err, HasSubstr("scene.xml: "));
}

TEST(MitsubaScene, EmittersMatchJson) {
  const SceneDesc x = xml(R"(
    <shape type="rectangle">
      <transform name="to_world"><rotate x="1" angle="90"/><translate y="1"/></transform>
      <bsdf type="diffuse"/>
      <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter>
    </shape>
    <emitter type="point"><point name="position" value="0, 0.5, 0"/><rgb name="intensity" value="1, 1, 2"/></emitter>
    <emitter type="spot">
      <transform name="to_world"><lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
      <float name="cutoff_angle" value="30"/><float name="beam_width" value="20"/><spectrum name="intensity" value="5"/>
    </emitter>
    <emitter type="directional"><vector name="direction" value="1, -1, 0"/><rgb name="irradiance" value="3"/></emitter>)");
  const double spotSolidAngle = 2 * kPi * ((1 - std::cos(glm::radians(20.0))) +
                                           0.5 * (std::cos(glm::radians(20.0)) - std::cos(glm::radians(30.0))));
  const SceneDesc j = json(fmt::format(R"({{
    "materials": {{"lamp": {{"type": "diffuse", "albedo": 0.5, "emission": [1, 2, 3]}}}},
    "shapes": [{{"type": "quad", "material": "lamp", "vertices": [[-1, 1, -1], [1, 1, -1], [1, 1, 1], [-1, 1, 1]]}}],
    "lights": [
      {{"type": "point", "position": [0, 0.5, 0], "power": [{}, {}, {}]}},
      {{"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "inner_angle": 20, "outer_angle": 30, "power": {}}},
      {{"type": "directional", "direction": [1, -1, 0], "irradiance": 3}}]}})",
      4 * kPi, 4 * kPi, 8 * kPi, 5 * spotSolidAngle));
  expectSameScene(x, j);
  EXPECT_NEAR(spotIntensity0(x.lights[1]).x, 5.0, 1e-5) << "Mitsuba's intensity is the on-axis W/sr";
  EXPECT_NEAR(pointIntensity(x.lights[0]).z, 2.0, 1e-6);
  // Mitsuba's default beam width: 3/4 of the cutoff angle.
  const SceneDesc d = xml(R"(<shape type="cube"/><emitter type="spot"><float name="cutoff_angle" value="40"/></emitter>)");
  EXPECT_NEAR(d.lights[0].innerAngleDeg, 30.0, 1e-12);
  expectNear(d.lights[0].direction, Vec3d(0, 0, 1), "spot default axis");
}

TEST(MitsubaScene, SensorMatchesJson) {
  const SceneDesc x = xml(R"(
    <integrator type="path"><integer name="max_depth" value="5"/></integrator>
    <sensor type="perspective">
      <float name="fov" value="60"/>
      <transform name="to_world"><lookat origin="0, 1, 3" target="0, 1, 0" up="0, 1, 0"/></transform>
      <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
      <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film>
    </sensor>
    <shape type="cube"/>)");
  const SceneDesc j = json(fmt::format(R"({{
    "camera": {{"position": [0, 1, 3], "look_at": [0, 1, 0], "fov_y": {}, "resolution": [64, 32]}},
    "materials": {{"m": {{"type": "diffuse", "albedo": 0.5}}}},
    "shapes": [{{"type": "box", "material": "m", "min": [-1, -1, -1], "max": [1, 1, 1]}}],
    "settings": {{"spp": 16, "max_depth": 4}}}})", glm::degrees(2 * std::atan(std::tan(glm::radians(30.0)) / 2))));
  expectSameScene(x, j);
}

TEST(MitsubaScene, FieldOfViewAxes) {
  // A 2:1 film: tan(fov_y/2) = tan(fov/2) / k with k = 2 (x, larger), 1 (y, smaller) and √5 (diagonal).
  const std::vector<std::pair<const char*, double>> axes = {{"x", 2}, {"y", 1}, {"smaller", 1}, {"larger", 2}, {"diagonal", std::sqrt(5.0)}};
  for (const auto& [axis, k] : axes) {
    SCOPED_TRACE(axis);
    const SceneDesc s = xml(fmt::format(R"(<sensor type="perspective"><float name="fov" value="50"/><string name="fov_axis" value="{}"/>
        <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film></sensor>
        <shape type="cube"/>)", axis));
    EXPECT_NEAR(std::tan(glm::radians(s.camera.fovYDeg) / 2), std::tan(glm::radians(25.0)) / k, 1e-12);
  }
  // No fov: a 50 mm lens on 36 × 24 mm film, the diagonal.
  const SceneDesc f = xml(R"(<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="300"/>
      <integer name="height" value="200"/></film></sensor><shape type="cube"/>)");
  EXPECT_NEAR(std::tan(glm::radians(f.camera.fovYDeg) / 2), 12.0 / 50.0, 1e-12);
  // A camera matrix (180° about y, Mitsuba's usual exported form) looks along −z.
  const SceneDesc m = xml(R"(<sensor type="perspective"><transform name="to_world">
      <matrix value="-1 0 0 0  0 1 0 1  0 0 -1 6.8  0 0 0 1"/></transform></sensor><shape type="cube"/>)");
  expectNear(m.camera.position, Vec3d(0, 1, 6.8), "matrix camera position");
  expectNear(glm::normalize(m.camera.lookAt - m.camera.position), Vec3d(0, 0, -1), "matrix camera direction");
}

TEST(MitsubaScene, DefaultsAreSubstituted) {
  const SceneDesc s = xml(R"(<default name="spp" value="32"/><default name="r" value="0.25"/><default name="s" value="sphere"/>
      <sensor type="perspective"><sampler type="independent"><integer name="sample_count" value="$spp"/></sampler></sensor>
      <shape type="$s"><float name="radius" value="$r"/><point name="center" value="$r, 0, 0"/></shape>)");
  EXPECT_EQ(s.settings.spp, 32);
  Vec3d lo, hi;
  s.bounds(lo, hi);
  expectNear(lo, Vec3d(0, -0.25, -0.25), "sphere bounds", 1e-6);
  expectNear(hi, Vec3d(0.5, 0.25, 0.25), "sphere bounds", 1e-6);
  try {
    xml(R"(<shape type="sphere"><float name="radius" value="$radius"/></shape>)");
    ADD_FAILURE() << "an undefined parameter must be an error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("$radius"));
    EXPECT_THAT(e.what(), HasSubstr("scene/shape/radius (line 2)"));
  }
}

TEST(MitsubaScene, UnreadPropertiesAreCountedOnOneLine) {
  testing::internal::CaptureStderr();
  xml(R"(<sensor type="perspective"><float name="near_clip" value="0.1"/>
      <film type="hdrfilm"><rfilter type="gaussian"/></film></sensor><shape type="cube"/>)");
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_THAT(err, HasSubstr("scene.xml: 2 properties not used by firstshot, skipped (scene/sensor/film/rfilter, "
                             "scene/sensor/near_clip)\n"));
}

TEST(MitsubaScene, ReferenceCyclesAndDeepNestingEndCleanly) {
  for (const char* cycle : {R"(<bsdf type="twosided" id="a"><ref id="a"/></bsdf><shape type="cube"><ref id="a"/></shape>)",
                            R"(<texture type="checkerboard" id="t"><ref name="color0" id="t"/></texture>
                               <shape type="cube"><bsdf type="diffuse"><ref name="reflectance" id="t"/></bsdf></shape>)"}) {
    try {
      xml(cycle);
      ADD_FAILURE() << "a <ref> cycle must be an error: " << cycle;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("nested more than 16 deep"));
    }
  }
  // 100 000 elements inside one another (skipped, counted): no recursion over the XML tree.
  std::string deep = "<shape type=\"cube\">";
  for (int i = 0; i < 100000; ++i) deep += "<x>";
  for (int i = 0; i < 100000; ++i) deep += "</x>";
  testing::internal::CaptureStderr();
  EXPECT_EQ(xml(deep + "</shape>").shapes.size(), 1u);
  EXPECT_THAT(testing::internal::GetCapturedStderr(), HasSubstr("1 property not used by firstshot, skipped (scene/shape/x)"));
}

namespace {

/// firstshot-preprocess --stats on the XML @p text: exit code 2 and one line with every part of @p parts.
void expectBadXml(const std::string& text, std::initializer_list<const char*> parts) {
  const std::string path = writeScene("scene.xml", text);
  const test::CommandResult r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats " + path);
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_THAT(r.output, HasSubstr("scene.xml: "));
  for (const char* p : parts) EXPECT_THAT(r.output, HasSubstr(p));
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
}

}  // namespace

TEST(MitsubaScene, UnsupportedPluginsAreNamed) {
  expectBadXml("<scene version=\"3.0.0\">\n  <shape type=\"cube\"/>\n  <shape type=\"bsplinecurve\"/>\n</scene>\n",
               {"scene/shape[2] (line 3)", "shape type \"bsplinecurve\" is not supported"});
  expectBadXml("<scene version=\"3.0.0\">\n<shape type=\"cube\">\n  <bsdf type=\"hair\"/>\n</shape>\n</scene>\n",
               {"scene/shape/bsdf (line 3)", "bsdf type \"hair\""});
  expectBadXml("<scene version=\"3.0.0\">\n<shape type=\"cube\"/>\n<emitter type=\"projector\"/>\n</scene>\n",
               {"scene/emitter (line 3)", "emitter type \"projector\""});
  expectBadXml("<scene version=\"3.0.0\">\n<shape type=\"cube\"><bsdf type=\"diffuse\">\n"
               "<spectrum name=\"reflectance\" value=\"700:0.1, 400:0.5\"/></bsdf></shape>\n</scene>\n",
               {"scene/shape/bsdf/reflectance (line 3)", "wavelengths must increase"});
  expectBadXml("<scene version=\"3.0.0\">\n<shape type=\"cube\">\n"
               "<bsdf type=\"conductor\"><string name=\"material\" value=\"Unobtainium\"/></bsdf></shape>\n</scene>\n",
               {"line 3", "Unobtainium"});
}

TEST(MitsubaScene, MalformedXmlGivesFileAndLine) {
  expectBadXml("<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n    <float name=\"x\" value=\"1\">\n  </shape>\n</scene>\n",
               {"malformed XML", "line 4, column"});
  expectBadXml("<scene>\n<shape type=\"cube\"/>\n</scene>\n", {"scene (line 1)", "version"});
}

namespace {

/// The image mean of each channel of @p desc rendered by the path tracer (patches of 0.25 m), and its standard error.
std::array<std::pair<double, double>, 3> renderMeans(const SceneDesc& desc, uint64_t seed) {
  const RenderScene scene(desc, 0.25);
  const auto run = test::renderPath(scene, IntegratorOptions{}, desc.settings.spp, seed);
  std::array<std::pair<double, double>, 3> r;
  for (int c = 0; c < 3; ++c) test::imageMean(run.film, c, r[c].first, r[c].second);
  return r;
}

/// The XML and the JSON scene rendered with different seeds: image means within 3σ, and not zero; with the same
/// seed, the same mean.
void expectSameImageMean(const SceneDesc& x, const SceneDesc& j) {
  const auto xs = renderMeans(x, 3), js = renderMeans(j, 4), sameSeed = renderMeans(x, 4);
  for (int c = 0; c < 3; ++c) {
    const auto [mx, sx] = xs[c];
    const auto [mj, sj] = js[c];
    fmt::print("channel {}: XML {:.5f} ± {:.5f}, JSON {:.5f} ± {:.5f}\n", c, mx, sx, mj, sj);
    EXPECT_GT(mj, 10 * sj);
    EXPECT_LE(std::abs(mx - mj), 3 * std::hypot(sx, sj)) << "channel " << c;
    // The same seed: the same image (the scenes are the same up to float rounding in the transforms).
    EXPECT_NEAR(sameSeed[c].first, mj, 1e-6 * mj) << "channel " << c;
  }
}

// A scene of its own: sensors in XML read better written out than assembled from parts.
const char* kXmlRoom = R"(
  <sensor type="perspective">
    <float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, 2, 2.5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/></film>
  </sensor>
  <shape type="rectangle">
    <transform name="to_world"><scale value="1.5"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></bsdf>
  </shape>)";

constexpr const char* kJsonRoom = R"(
  "camera": {{"position": [0, 2, 2.5], "look_at": [0, 0, 0], "fov_y": {}, "resolution": [32, 24]}},
  "settings": {{"spp": 16}},)";

std::string jsonRoom() { return fmt::format(kJsonRoom, glm::degrees(2 * std::atan(std::tan(glm::radians(25.0)) * 0.75))); }

const char* kJsonFloor = R"({"type": "quad", "material": "floor", "vertices": [[-1.5, 0, 1.5], [1.5, 0, 1.5], [1.5, 0, -1.5], [-1.5, 0, -1.5]]})";

}  // namespace

TEST(MitsubaScene, AreaLightRenderMatchesJson) {
  const SceneDesc x = xml(std::string(kXmlRoom) + R"(
    <shape type="rectangle">
      <transform name="to_world"><scale value="0.3"/><rotate x="1" angle="90"/><translate y="1"/></transform>
      <emitter type="area"><rgb name="radiance" value="4, 3, 2"/></emitter>
    </shape>)");
  const SceneDesc j = json("{" + jsonRoom() + R"(
    "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.5, 0.4]}, "lamp": {"type": "diffuse", "albedo": 0.5, "emission": [4, 3, 2]}},
    "shapes": [)" + kJsonFloor + R"(,
      {"type": "quad", "material": "lamp", "vertices": [[-0.3, 1, -0.3], [0.3, 1, -0.3], [0.3, 1, 0.3], [-0.3, 1, 0.3]]}]})");
  expectSameScene(x, j);
  expectSameImageMean(x, j);
}

TEST(MitsubaScene, PointAndSpotRenderMatchesJson) {
  const SceneDesc x = xml(std::string(kXmlRoom) + R"(
    <emitter type="point"><point name="position" value="0.5, 1, 0"/><rgb name="intensity" value="1, 2, 3"/></emitter>
    <emitter type="spot">
      <transform name="to_world"><lookat origin="-0.5, 1.5, 0" target="-0.5, 0, 0.5" up="0, 1, 0"/></transform>
      <float name="cutoff_angle" value="35"/><float name="beam_width" value="25"/><rgb name="intensity" value="6, 4, 2"/>
    </emitter>)");
  const double spot = 2 * kPi * ((1 - std::cos(glm::radians(25.0))) + 0.5 * (std::cos(glm::radians(25.0)) - std::cos(glm::radians(35.0))));
  const SceneDesc j = json("{" + jsonRoom() + fmt::format(R"(
    "materials": {{"floor": {{"type": "diffuse", "albedo": [0.6, 0.5, 0.4]}}}},
    "shapes": [{}],
    "lights": [{{"type": "point", "position": [0.5, 1, 0], "power": [{}, {}, {}]}},
      {{"type": "spot", "position": [-0.5, 1.5, 0], "direction": [0, -1.5, 0.5], "inner_angle": 25, "outer_angle": 35,
        "power": [{}, {}, {}]}}]}})", kJsonFloor, 4 * kPi, 8 * kPi, 12 * kPi, 6 * spot, 4 * spot, 2 * spot));
  expectSameScene(x, j);
  expectSameImageMean(x, j);
}
