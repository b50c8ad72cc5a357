// Mitsuba's conductor and roughconductor read as a mirror or the pbr material with a conductor's Fresnel
// (common/formats/mitsuba/mitsuba_bsdf.cpp): presets, eta/k over ext_eta, Mitsuba 0.x defaults, the microfacet distribution, the JSON
// keys that say the same (common/formats/json/scene_json.cpp) and their errors; a mirror of material "none" rendered, reflecting
// an emitter exactly, and a tinted copper mirror reflecting tint × F0; the Veach MIS scene's plates as the file says.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <filesystem>

#include "common/formats/load_scene.h"
#include "common/materials/conductor_presets.h"
#include "common/util/error.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;

namespace {

/// A scene file @p name of @p text in a fresh folder, loaded (and validated) through loadScene.
SceneDesc load(const std::string& name, const std::string& text) {
  const std::string path = test::tempDir() + "/" + name;
  test::writeText(path, text);
  return loadScene(path);
}

/// A Mitsuba scene of @p version around @p body (one rectangle with the bsdf of id "b"), its material "b".
MaterialDesc xmlBsdf(const std::string& bsdf, const std::string& version = "3.0.0") {
  const SceneDesc s = load("scene.xml", "<scene version=\"" + version + "\">\n" + bsdf +
                                            "\n<shape type=\"rectangle\"><ref id=\"b\"/></shape>\n</scene>\n");
  return s.materials[size_t(s.findMaterial("b"))];
}

/// A JSON scene with one quad of material @p material (a JSON object), that material.
MaterialDesc jsonMaterial(const std::string& material) {
  const SceneDesc s = load("scene.json", R"({"materials": {"b": )" + material + R"(},
    "shapes": [{"type": "quad", "material": "b", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}]})");
  return s.materials[0];
}

/// The message of the InputError that loading @p text as @p name throws ("" if none).
std::string loadError(const std::string& name, const std::string& text) {
  try {
    load(name, text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expectSameConductor(const MaterialDesc& a, const MaterialDesc& b) {
  EXPECT_EQ(a.type, b.type);
  ASSERT_EQ(bool(a.conductor), bool(b.conductor));
  if (a.conductor)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.conductor->eta()[c], b.conductor->eta()[c], 1e-6f * b.conductor->eta()[c]) << c;
      EXPECT_NEAR(a.conductor->k()[c], b.conductor->k()[c], 1e-6f * b.conductor->k()[c]) << c;
    }
  EXPECT_EQ(a.microfacet, b.microfacet);
  EXPECT_EQ(a.albedo, b.albedo);
  EXPECT_EQ(a.specular, b.specular);
  EXPECT_NEAR(a.roughness, b.roughness, 1e-7f);
  EXPECT_EQ(a.metallic, b.metallic);
}

}  // namespace

TEST(MitsubaConductor, SmoothConductorIsAMirrorWithTheFresnel) {
  const MaterialDesc au = xmlBsdf(R"(<bsdf type="conductor" id="b"><string name="material" value="Au"/>
    <rgb name="specular_reflectance" value="0.5, 0.6, 0.7"/></bsdf>)");
  expectSameConductor(au, jsonMaterial(R"({"type": "mirror", "specular": [0.5, 0.6, 0.7], "conductor": "Au"})"));
  EXPECT_EQ(au.conductor, conductorPreset("Au"));
  // Mitsuba 3's default material is "none", the ideal mirror: η = 0, k = 1.
  const MaterialDesc none = xmlBsdf(R"(<bsdf type="conductor" id="b"/>)");
  EXPECT_EQ(none.type, MaterialType::Mirror);
  EXPECT_EQ(none.conductor, ConductorFresnel());
  EXPECT_EQ(none.specular, Color(1.0f));
}

TEST(MitsubaConductor, RoughConductorIsThePbrMetalWithTheFresnel) {
  const MaterialDesc rc = xmlBsdf(R"(<bsdf type="roughconductor" id="b"><float name="alpha" value="0.09"/>
    <rgb name="specular_reflectance" value="0.3"/><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.45, 2.14"/>
    <float name="ext_eta" value="1.25"/><boolean name="sample_visible" value="false"/></bsdf>)");
  expectSameConductor(rc, jsonMaterial(R"({"type": "pbr", "base_color": 0.3, "metallic": 1, "roughness": 0.3,
    "eta": [0.16, 0.72, 0.88], "k": [3.12, 1.96, 1.712], "microfacet": "beckmann"})"));
  // distribution: ggx as asked; phong as Beckmann of the same alpha (noted); anything else an error with the line.
  EXPECT_EQ(xmlBsdf(R"(<bsdf type="roughconductor" id="b"><string name="distribution" value="ggx"/></bsdf>)").microfacet,
            MicrofacetModel::Ggx);
  testing::internal::CaptureStderr();
  EXPECT_EQ(xmlBsdf(R"(<bsdf type="roughconductor" id="b"><string name="distribution" value="phong"/></bsdf>)").microfacet,
            MicrofacetModel::Beckmann);
  EXPECT_THAT(testing::internal::GetCapturedStderr(), HasSubstr("phong microfacet distribution rendered as Beckmann"));
  const std::string err = loadError("scene.xml", R"(<scene version="3.0.0">
    <shape type="rectangle"><bsdf type="roughconductor"><string name="distribution" value="ashikhmin"/></bsdf></shape></scene>)");
  EXPECT_THAT(err, HasSubstr("scene.xml: scene/shape/bsdf (line 2)"));
  EXPECT_THAT(err, HasSubstr("unknown microfacet distribution \"ashikhmin\""));
}

TEST(MitsubaConductor, PresetsEtaKAndVersionDefaults) {
  // eta alone: k from the preset (Mitsuba 3's "none": 1).
  EXPECT_EQ(xmlBsdf(R"(<bsdf type="conductor" id="b"><rgb name="eta" value="1.5"/></bsdf>)").conductor,
            ConductorFresnel(Color(1.5f), Color(1.0f)));
  // A preset with k replaced.
  const MaterialDesc cuK = xmlBsdf(R"(<bsdf type="conductor" id="b"><string name="material" value="Cu"/><float name="k" value="2"/></bsdf>)");
  EXPECT_EQ(cuK.conductor, ConductorFresnel(conductorPreset("Cu")->eta(), Color(2.0f)));
  // Mitsuba 0.x: material Cu and ext_eta air by default, camelCase names.
  const MaterialDesc v0 = xmlBsdf(R"(<bsdf type="roughconductor" id="b"><rgb name="specularReflectance" value="0.5"/></bsdf>)", "0.6.0");
  const float air = 1.000277f;
  ASSERT_TRUE(v0.conductor);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(v0.conductor->eta()[c], conductorPreset("Cu")->eta()[c] / air, 1e-6f);
    EXPECT_NEAR(v0.conductor->k()[c], conductorPreset("Cu")->k()[c] / air, 1e-6f);
  }
  EXPECT_EQ(v0.albedo, Color(0.5f));
  const std::string err = loadError("scene.xml", R"(<scene version="3.0.0">
    <shape type="rectangle">
      <bsdf type="conductor"><string name="material" value="Unobtainium"/></bsdf></shape></scene>)");
  EXPECT_THAT(err, HasSubstr("(line 3)"));
  EXPECT_THAT(err, HasSubstr("unknown conductor material \"Unobtainium\" (none, Ag, Al"));
}

TEST(JsonConductor, KeysAndErrors) {
  EXPECT_FALSE(jsonMaterial(R"({"type": "mirror"})").conductor) << "a mirror without the keys keeps its reflectance";
  EXPECT_FALSE(jsonMaterial(R"({"type": "pbr", "metallic": 1})").conductor);
  EXPECT_EQ(jsonMaterial(R"({"type": "pbr", "metallic": 1})").microfacet, MicrofacetModel::Ggx);
  EXPECT_EQ(jsonMaterial(R"({"type": "mirror", "eta": 0.5, "k": [3, 2, 1]})").conductor,
            ConductorFresnel(Color(0.5f), Color(3.0f, 2.0f, 1.0f)));
  const auto err = [](const std::string& material) {
    return loadError("scene.json", R"({"materials": {"b": )" + material + R"(},
      "shapes": [{"type": "quad", "material": "b", "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]}]})");
  };
  EXPECT_THAT(err(R"({"type": "mirror", "conductor": "Cu", "eta": 1})"), HasSubstr("materials.b.conductor: give either"));
  EXPECT_THAT(err(R"({"type": "mirror", "eta": 1})"), HasSubstr("missing key \"k\""));
  EXPECT_THAT(err(R"({"type": "pbr", "conductor": "Mithril"})"), HasSubstr("unknown conductor \"Mithril\""));
  EXPECT_THAT(err(R"({"type": "pbr", "k": -1, "eta": 1})"), HasSubstr("must not be negative"));
  EXPECT_THAT(err(R"({"type": "pbr", "microfacet": "phong"})"), HasSubstr("unknown microfacet distribution"));
  EXPECT_THAT(err(R"({"type": "diffuse", "conductor": "Au"})"), HasSubstr("unknown key \"conductor\""));
}

namespace {

/// A camera at the origin looking down −z through @p fov degrees at a 2 × 2 m mirror at z = −1 (of bsdf @p mirror),
/// facing an emitter of radiance (1, 2, 3) at z = +1 behind the camera (black, 8 × 8 m, facing −z) that the mirror
/// shows in every pixel; one camera path per sample: camera → mirror → emitter.
std::string mirrorScene(const std::string& mirror, double fov) {
  return fmt::format(R"(<scene version="3.0.0">
  <sensor type="perspective"><float name="fov" value="{}"/>
    <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
  <shape type="rectangle"><transform name="to_world"><translate z="-1"/></transform>{}</shape>
  <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate y="1" angle="180"/><translate z="1"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf><emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
</scene>)", fov, mirror);
}

/// Every pixel of @p xml rendered by the path tracer, checked against @p expected (per channel) within @p rel.
void expectEveryPixel(const std::string& xml, const Color& expected, double rel) {
  testing::internal::CaptureStderr();
  const SceneDesc desc = load("scene.xml", xml);
  testing::internal::GetCapturedStderr();
  const RenderScene scene(desc);
  const auto run = test::renderPath(scene, IntegratorOptions{}, desc.settings.spp, 1);
  for (int y = 0; y < run.film.height(); ++y)
    for (int x = 0; x < run.film.width(); ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(run.film.mean(x, y)[c], expected[c], rel * expected[c]) << x << ", " << y << " channel " << c;
}

}  // namespace

TEST(MitsubaConductor, MirrorOfMaterialNoneReflectsExactly) {
  expectEveryPixel(mirrorScene(R"(<bsdf type="conductor"><string name="material" value="none"/></bsdf>)", 40),
                   Color(1.0f, 2.0f, 3.0f), 1e-6);
  // Copper tinted 0.5, seen within 1° of normal incidence: 0.5 × F0 × the emitter (F varies by < 1e-4 there).
  const Color f0 = conductorPreset("Cu")->normalIncidence();
  expectEveryPixel(mirrorScene(R"(<bsdf type="conductor"><string name="material" value="Cu"/>
    <rgb name="specular_reflectance" value="0.5"/></bsdf>)", 2),
                   0.5f * f0 * Color(1.0f, 2.0f, 3.0f), 2e-4);
}

TEST(MitsubaConductor, VeachMisPlatesAreTheFilesCopper) {
  const std::string path = test::source("../shared/scenes/veach-mis/scene.xml");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "../shared/scenes/veach-mis is not here (public scenes, read-only)";
  testing::internal::CaptureStderr();
  const SceneDesc s = loadScene(path);
  testing::internal::GetCapturedStderr();
  int plates = 0;
  for (const auto& [id, alpha] : {std::pair{"SmoothBSDF", 0.01}, std::pair{"GlossyBSDF", 0.05}, std::pair{"RoughBSDF", 0.1},
                                  std::pair{"SuperRoughBSDF", 0.25}}) {
    const int m = s.findMaterial(id);
    ASSERT_GE(m, 0) << id;
    const MaterialDesc& d = s.materials[size_t(m)];
    EXPECT_EQ(d.type, MaterialType::Pbr);
    EXPECT_EQ(d.albedo, Color(0.3f)) << "specular_reflectance: the tint";
    EXPECT_EQ(d.microfacet, MicrofacetModel::Beckmann);
    EXPECT_NEAR(d.roughness, std::sqrt(alpha), 1e-6);
    EXPECT_EQ(d.conductor, conductorPreset("Cu")) << "the file's eta and k are Mitsuba's RGB copper";
    ++plates;
  }
  EXPECT_EQ(plates, 4);
}
