// Scene loading: the shipped scenes parse, and every kind of bad input gets one clear message
// naming the file and element, with exit code 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "common/formats/json/scene_json.h"
#include "common/formats/load_scene.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/test_util.h"

using ::testing::HasSubstr;
using namespace firstshot;

namespace {

const char* kValid = R"({
  "camera": {"position": [0, 1, 3], "look_at": [0, 1, 0], "fov_y": 45, "resolution": [64, 48]},
  "materials": {"white": {"type": "diffuse", "albedo": 0.5},
                "lamp": {"type": "diffuse", "emission": [10, 10, 10]}},
  "shapes": [{"type": "quad", "material": "white", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
             {"type": "quad", "material": "lamp", "vertices": [[-0.1,2,-0.1],[0.1,2,-0.1],[0.1,2,0.1],[-0.1,2,0.1]]}],
  "lights": [{"type": "point", "position": [0, 1, 0], "power": 10}]
})";

/// Runs the preprocessor on a scene text and returns the result.
test::CommandResult runOn(const std::string& text, const std::string& name = "scene.json") {
  const std::string dir = test::tempDir();
  const std::string path = dir + "/" + name;
  test::writeText(path, text);
  return test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats " + path);
}

/// Replaces the first occurrence of @p from in the valid scene.
std::string variant(const std::string& from, const std::string& to) {
  std::string s = kValid;
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

void expectBadInput(const test::CommandResult& r, std::initializer_list<const char*> parts) {
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_THAT(r.output, HasSubstr("scene.json")) << "the message names the file";
  for (const char* p : parts) EXPECT_THAT(r.output, HasSubstr(p));
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
}

}  // namespace

TEST(SceneParse, ShippedScenesLoad) {
  for (const char* name : {"cornell", "many-lights", "point-over-plane", "sierpinski-glossy", "ward-sphere"}) {
    SCOPED_TRACE(name);
    const SceneDesc s = loadScene(test::source(std::string("scenes/") + name + ".json"));
    EXPECT_FALSE(s.shapes.empty());
    EXPECT_FALSE(s.lights.empty());
    EXPECT_TRUE(s.camera.given);
  }
}

TEST(SceneParse, CornellHasOfficialDataInMetres) {
  const SceneDesc s = loadScene(test::source("scenes/cornell.json"));
  ASSERT_EQ(s.lights.size(), 1u);
  const LightDesc& light = s.lights[0];
  EXPECT_EQ(light.type, LightType::Area);
  const ShapeDesc& shape = s.shapes[light.shape];
  // 130 mm x 105 mm, facing down, 0.5 mm under the ceiling at 548.8 mm.
  EXPECT_NEAR(shapeArea(shape), 0.130 * 0.105, 1e-12);
  for (const auto& v : shape.vertices) EXPECT_NEAR(v.y, 0.5483, 1e-12);
  const MaterialDesc& m = s.materials[shape.material];
  EXPECT_EQ(m.emission, Color(17, 12, 4));
  EXPECT_NEAR(s.camera.fovYDeg, 39.3077, 1e-9);
  EXPECT_NEAR(s.camera.position.z, -0.8, 1e-12);
}

TEST(SceneParse, ManyLightsHas64PointLights) {
  const SceneDesc s = loadScene(test::source("scenes/many-lights.json"));
  EXPECT_EQ(std::count_if(s.lights.begin(), s.lights.end(), [](const LightDesc& l) { return l.type == LightType::Point; }), 64);
}

TEST(SceneParse, ValidSceneFromText) {
  SceneDesc s = parseSceneJson(kValid, "mem.json");
  validateScene(s);
  EXPECT_EQ(s.materials.size(), 2u);
  ASSERT_EQ(s.lights.size(), 2u);  // the point light and the emissive quad
  EXPECT_EQ(s.lights[1].type, LightType::Area);
  EXPECT_EQ(s.camera.width, 64);
  EXPECT_EQ(s.camera.height, 48);
}

TEST(SceneParse, TransformsAndShapes) {
  const std::string text = R"({
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "box", "material": "m", "min": [0,0,0], "max": [1,2,3], "transform": {"translate": [1,0,0], "scale": 2}},
               {"type": "sphere", "material": "m", "center": [0,0,0], "radius": 1, "subdivisions": 4}]})";
  SceneDesc s = parseSceneJson(text, "mem.json");
  validateScene(s);
  EXPECT_NEAR(shapeArea(s.shapes[0]), 4.0 * 2 * (2 + 6 + 3), 1e-9);
  const double a = shapeArea(s.shapes[1]);
  EXPECT_LT(a, 4 * kPi);
  EXPECT_GT(a, 0.99 * 4 * kPi);  // 5120 triangles inscribed in the unit sphere
  EXPECT_FALSE(s.camera.given);  // framed automatically
  Vec3d lo, hi;
  s.bounds(lo, hi);
  EXPECT_EQ(lo, Vec3d(-1, -1, -1));
  EXPECT_EQ(hi, Vec3d(3, 4, 6));
}

TEST(SceneParse, HashIgnoresCameraButNotGeometry) {
  SceneDesc a = parseSceneJson(kValid, "a.json");
  validateScene(a);
  SceneDesc b = parseSceneJson(variant("\"position\": [0, 1, 3]", "\"position\": [0, 2, 3]"), "b.json");
  validateScene(b);
  SceneDesc c = parseSceneJson(variant("[1,0,1],[1,0,-1]", "[1,0,1.5],[1,0,-1]"), "c.json");
  validateScene(c);
  EXPECT_EQ(hashScene(a), hashScene(b));
  EXPECT_NE(hashScene(a), hashScene(c));
}

TEST(SceneParse, PbrMaterialKeysAndDefaults) {
  const std::string pbr = R"("white": {"type": "pbr", "base_color": [0.9, 0.5, 0.1], "metallic": 0.25, "roughness": 0.4, "ior": 1.4})";
  SceneDesc s = parseSceneJson(variant(R"("white": {"type": "diffuse", "albedo": 0.5})", pbr), "mem.json");
  validateScene(s);
  const MaterialDesc& m = s.materials[size_t(s.findMaterial("white"))];
  EXPECT_EQ(m.type, MaterialType::Pbr);
  EXPECT_EQ(m.albedo, Color(0.9f, 0.5f, 0.1f));
  EXPECT_EQ(m.metallic, 0.25f);
  EXPECT_EQ(m.roughness, 0.4f);
  EXPECT_EQ(m.ior, 1.4f);
  // glTF's defaults: a white rough metal of ior 1.5.
  SceneDesc d = parseSceneJson(variant(R"("white": {"type": "diffuse", "albedo": 0.5})", R"("white": {"type": "pbr"})"), "d.json");
  validateScene(d);
  const MaterialDesc& dm = d.materials[size_t(d.findMaterial("white"))];
  EXPECT_EQ(dm.albedo, Color(1.0f));
  EXPECT_EQ(dm.metallic, 1.0f);
  EXPECT_EQ(dm.roughness, 1.0f);
  EXPECT_EQ(dm.ior, 1.5f);
  // metallic and roughness change the scene's hash (other materials' hashes do not read them).
  SceneDesc r = parseSceneJson(variant(R"("white": {"type": "diffuse", "albedo": 0.5})", R"("white": {"type": "pbr", "roughness": 0.5})"), "r.json");
  validateScene(r);
  EXPECT_NE(hashScene(d), hashScene(r));
}

TEST(SceneBadInput, PbrKeysAreChecked) {
  const std::string white = R"("white": {"type": "diffuse", "albedo": 0.5})";
  expectBadInput(runOn(variant(white, R"("white": {"type": "pbr", "metallic": 1.5})")),
                 {"materials.white.metallic", "must be in [0, 1]"});
  expectBadInput(runOn(variant(white, R"("white": {"type": "pbr", "roughness": -0.1})")),
                 {"materials.white.roughness", "must be in [0, 1]"});
  expectBadInput(runOn(variant(white, R"("white": {"type": "pbr", "base_color": [1.2, 0, 0]})")),
                 {"materials.white.base_color", "must be in [0, 1]"});
  expectBadInput(runOn(variant(white, R"("white": {"type": "pbr", "ior": 0})")), {"materials.white.ior", "must be positive"});
  expectBadInput(runOn(variant(white, R"("white": {"type": "pbr", "albedo": 0.5})")),
                 {"materials.white", "unknown key \"albedo\"", "base_color"});
  expectBadInput(runOn(variant(white, R"("white": {"type": "shiny"})")), {"materials.white.type", "pbr"});
}

TEST(SceneBadInput, ValidSceneExitsZero) {
  const auto r = runOn(kValid);
  EXPECT_EQ(r.exitCode, 0) << r.output;
}

TEST(SceneBadInput, MissingSceneFile) {
  const auto r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats /nonexistent/scene.json");
  expectBadInput(r, {"/nonexistent/scene.json", "no such file"});
}

TEST(SceneBadInput, MalformedJsonGivesLineAndColumn) {
  const auto r = runOn("{\n  \"materials\": {\n    \"white\": {\"type\": \"diffuse\" \"albedo\": 0.5}\n  }\n}\n");
  expectBadInput(r, {"line 3, column", "malformed JSON"});
}

// The bad-input cases stay spelled out one by one: each shows the JSON it breaks and the message it expects.
TEST(SceneBadInput, UnknownKey) {
  const auto r = runOn(variant("\"fov_y\": 45", "\"fov_y\": 45, \"fovy\": 45"));
  expectBadInput(r, {"camera", "unknown key \"fovy\""});
}

TEST(SceneBadInput, UnknownKeyInShape) {
  const auto r = runOn(variant("\"type\": \"quad\", \"material\": \"white\"", "\"type\": \"quad\", \"colour\": 1, \"material\": \"white\""));
  expectBadInput(r, {"shapes[0]", "unknown key \"colour\""});
}

TEST(SceneBadInput, MissingMeshFile) {
  const auto r = runOn(variant("{\"type\": \"quad\", \"material\": \"white\", \"vertices\": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}",
                               "{\"type\": \"mesh\", \"material\": \"white\", \"file\": \"missing-bunny.obj\"}"));
  expectBadInput(r, {"shapes[0].file", "missing-bunny.obj"});
}

TEST(SceneBadInput, InfiniteNumber) {
  const auto r = runOn(variant("\"power\": 10", "\"power\": 1e999"));
  expectBadInput(r, {"1e999", "must be finite"});
}

TEST(SceneBadInput, NaNInMeshFile) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 1\nf 1 2 3\n");
  test::writeText(dir + "/scene.json", variant("{\"type\": \"quad\", \"material\": \"white\", \"vertices\": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}",
                                               "{\"type\": \"mesh\", \"material\": \"white\", \"file\": \"nan.obj\"}"));
  const auto r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats " + dir + "/scene.json");
  expectBadInput(r, {"shapes[0]", "not finite"});
}

TEST(SceneBadInput, NegativeAlbedo) {
  const auto r = runOn(variant("\"albedo\": 0.5", "\"albedo\": [0.5, -0.1, 0.5]"));
  expectBadInput(r, {"materials.white.albedo[1]", "negative"});
}

TEST(SceneBadInput, NegativeRadius) {
  const auto r = runOn(variant("{\"type\": \"quad\", \"material\": \"white\", \"vertices\": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}",
                               "{\"type\": \"sphere\", \"material\": \"white\", \"center\": [0,0,0], \"radius\": -1}"));
  expectBadInput(r, {"shapes[0].radius", "must be positive"});
}

TEST(SceneBadInput, UnknownMaterial) {
  const auto r = runOn(variant("\"material\": \"white\"", "\"material\": \"marble\""));
  expectBadInput(r, {"shapes[0].material", "unknown material \"marble\""});
}

TEST(SceneBadInput, UnknownShapeType) {
  const auto r = runOn(variant("\"type\": \"quad\"", "\"type\": \"torus\""));
  expectBadInput(r, {"shapes[0].type", "unknown shape type \"torus\""});
}

TEST(SceneBadInput, InputErrorCarriesFileAndElement) {
  try {
    parseSceneJson(variant("\"material\": \"white\"", "\"material\": \"marble\""), "x.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "x.json");
    EXPECT_EQ(e.element(), "shapes[0].material");
  }
}

// The refinement and light-tessellation settings: refused where they make no sense, with their key.
TEST(SceneBadInput, RefinementSettings) {
  auto withSettings = [](const std::string& settings) {
    return variant("\"power\": 10}]", "\"power\": 10}], \"settings\": " + settings);
  };
  expectBadInput(runOn(withSettings(R"({"patch_size": 0.5, "min_patch_size": 1})")),
                 {"settings.min_patch_size", "must not exceed settings.patch_size"});
  expectBadInput(runOn(withSettings(R"({"min_patch_size": -0.1})")), {"settings.min_patch_size"});
  expectBadInput(runOn(withSettings(R"({"refine_tolerance": 0})")), {"settings.refine_tolerance"});
  expectBadInput(runOn(withSettings(R"({"light_tolerance": -1})")), {"settings.light_tolerance"});
  EXPECT_EQ(runOn(withSettings(R"({"patch_size": 0.5, "min_patch_size": 0.1, "refine_tolerance": 0.05, "light_tolerance": 0.02})"))
                .exitCode,
            0);
}

// Zero-area and duplicate faces: skipped with one line per file on stderr, as other renderers tolerate them.
namespace {

/// 4 good triangles (two quads), 3 zero-area ones, 2 duplicates (one rotated) and the first triangle reversed
/// (not a duplicate: the other side).
const char* kFlawedObj =
    "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 2 0 0\nv 2 0 1\nv 3 0 0\n"
    "f 1 4 3\nf 1 3 2\nf 2 3 6\nf 2 6 5\n"  // good
    "f 1 2 5\nf 1 1 3\nf 2 5 7\n"            // collinear, repeated vertex, collinear
    "f 4 3 1\nf 1 4 3\n"                     // the first, rotated, and again
    "f 1 3 4\n";                             // the first, reversed

/// kValid with its floor replaced by a mesh shape of @p obj, written to a fresh directory; @return the scene's path.
std::string sceneWithMesh(const std::string& obj, const std::string& material = "white") {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/flawed.obj", obj);
  test::writeText(dir + "/scene.json",
                  variant("{\"type\": \"quad\", \"material\": \"white\", \"vertices\": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}",
                          "{\"type\": \"mesh\", \"material\": \"" + material + "\", \"file\": \"flawed.obj\"}"));
  return dir + "/scene.json";
}

}  // namespace

TEST(SceneSkippedFaces, ZeroAreaAndDuplicateTrianglesAreSkippedWithOneLine) {
  const std::string path = sceneWithMesh(kFlawedObj);
  testing::internal::CaptureStderr();
  const SceneDesc s = loadScene(path);
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].faces.size(), 10u - 5u);
  EXPECT_NEAR(shapeArea(s.shapes[0]), 4 * 0.5 + 0.5, 1e-12);  // the reversed triangle stays
  const std::string dir = std::filesystem::path(path).parent_path().string();
  EXPECT_EQ(err, path + ": skipped 5 of 10 triangles of " + dir + "/flawed.obj (3 zero-area, 2 duplicates)\n");
  // The tool: the same line, exit 0.
  const auto r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats " + path);
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("skipped 5 of 10 triangles of " + dir + "/flawed.obj (3 zero-area, 2 duplicates)"));
}

TEST(SceneSkippedFaces, DirectObjSceneToo) {
  const std::string dir = test::tempDir();
  test::writeText(dir + "/flawed.obj", kFlawedObj);
  testing::internal::CaptureStderr();
  const SceneDesc s = loadScene(dir + "/flawed.obj");
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            dir + "/flawed.obj: skipped 5 of 10 triangles (3 zero-area, 2 duplicates)\n" +  // the one line, and
            dir + "/flawed.obj: no lights, no emissive surfaces, no sky: the images are black\n");  // it has none
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(s.shapes[0].faces.size(), 5u);
}

TEST(SceneSkippedFaces, ShapeOfSkippedFacesIsDroppedAndAreaLightsFollow) {
  // The floor quad is a line: dropped. The lamp (an area light) is then shapes[0], and its light points at it.
  testing::internal::CaptureStderr();
  SceneDesc s = parseSceneJson(variant("[[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]", "[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]"),
                               "mem.json");
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "mem.json: skipped 2 of 3 faces (2 zero-area, 0 duplicates); dropped 1 shape with no face left (shapes[0])\n");
  validateScene(s);
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(s.shapes[0].name, "shapes[1]");
  const auto area = std::find_if(s.lights.begin(), s.lights.end(), [](const LightDesc& l) { return l.type == LightType::Area; });
  ASSERT_NE(area, s.lights.end());
  EXPECT_EQ(area->shape, 0);
  // A zero-area emitter is dropped likewise (it emits nothing); the tool goes on.
  const auto r = runOn(variant("[[-0.1,2,-0.1],[0.1,2,-0.1],[0.1,2,0.1],[-0.1,2,0.1]]", "[[0,2,0],[0,2,0],[0,2,0],[0,2,0]]"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("dropped 1 shape with no face left (shapes[1])"));
}

TEST(SceneSkippedFaces, NoShapeLeftAndNonFiniteVerticesAreErrors) {
  expectBadInput(runOn(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]]}]})"),
                 {"shapes", "every face of every shape is zero-area or a duplicate"});
  // A NaN vertex in a mesh whose only triangle it makes degenerate: still refused, not skipped.
  const auto r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats " +
                           sceneWithMesh("v 0 0 0\nv 1 0 0\nv nan 0 0\nf 1 2 3\n"));
  expectBadInput(r, {"shapes[0]", "not finite"});
}
