// A JSON scene that places a public asset with its own materials (a mesh shape without "material"), and the
// line a scene without any light prints (scenes users bring).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/materials/texture.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/shipped_first_shot.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

using ::testing::HasSubstr;

/// The shipped scene with the crate three times (scenes/gltf-crates.json, scenes/assets/crate.gltf).
TEST(SceneAssets, MeshWithoutMaterialTakesTheFilesMaterials) {
  const SceneDesc s = loadScene(test::source("scenes/gltf-crates.json"));
  ASSERT_EQ(s.shapes.size(), 9u);      // 6 quads and one mesh per placed box
  ASSERT_EQ(s.materials.size(), 6u);   // the JSON's 3 and each placement's copy of the file's one
  for (size_t i = 6; i < 9; ++i) {
    const ShapeDesc& box = s.shapes[i];
    EXPECT_THAT(box.name, HasSubstr("box " + std::to_string(i - 5)));
    EXPECT_EQ(box.faces.size(), 12u);
    EXPECT_TRUE(box.hasUv());
    const MaterialDesc& m = s.materials[size_t(box.material)];
    EXPECT_EQ(m.type, MaterialType::Pbr);      // glTF metallic-roughness: factors 1, the textures give the values
    EXPECT_FLOAT_EQ(m.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.roughness, 1.0f);
    ASSERT_TRUE(m.albedoTexture);              // ../textures/floor.png, 256 × 256
    EXPECT_EQ(m.albedoTexture->image->width, 256);
    EXPECT_TRUE(m.metallicRoughnessTexture);   // ../textures/crate_mr.png
  }
  // Box 1: the unit cube scaled by 0.5, turned 20° about y, its centre at (1, 0.25, 1.1).
  Vec3d lo(1e9), hi(-1e9);
  for (const Vec3d& v : s.shapes[6].vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
  const double pi = 3.14159265358979;
  const double w = 0.5 * (std::cos(20 * pi / 180) + std::sin(20 * pi / 180));
  EXPECT_NEAR(hi.x - lo.x, w, 1e-6);
  EXPECT_NEAR(hi.z - lo.z, w, 1e-6);
  EXPECT_NEAR(lo.y, 0.0, 1e-6);
  EXPECT_NEAR(hi.y, 0.5, 1e-6);
  EXPECT_NEAR(0.5 * (lo.x + hi.x), 1.0, 1e-6);
}

/// scenes/gltf-samples.json: Khronos' TextureTransformTest chart and BoxTextured from Debian's assimp-testmodels
/// (installed by scripts/install-deps.sh). assimp numbers the chart's meshes and materials in the order it meets
/// them (node 3's child markers before node 3's own mesh), not the file's: each mesh must still get its own material
/// — the tiles of the bottom row the arrow texture with their KHR_texture_transform, the markers the marker images
/// (before the fix the three tiles drew as "Correct", "NotSupported" and "Error" and the markers as arrows).
TEST(SceneAssets, PublicGltfSamplesKeepTheirMaterials) {
  const std::string chart = "/usr/share/assimp/models/glTF2/textureTransform/TextureTransformTest.gltf";
  ASSERT_TRUE(std::filesystem::exists(chart)) << chart << " is missing: install assimp-testmodels (scripts/install-deps.sh)";
  const SceneDesc s = loadScene(test::source("scenes/gltf-samples.json"));
  struct Expect {
    std::string mesh, image;
    float rotation = 0.0f, scale = 1.0f;
  };
  const std::vector<Expect> expected = {
      // images: 0 UV.png, 1 Arrow.png, 2 Correct.png, 3 NotSupported.png, 4 Error.png
      {"Offset U", "images[0]"}, {"Rotation", "images[1]", 0.39269908f}, {"Scale", "images[1]", 0.0f, 1.5f},
      {"All", "images[1]", 0.3f, 1.5f}, {"Correct Marker", "images[2]"}, {"Not Supported Marker", "images[3]"},
      {"Error Marker", "images[4]"}};
  size_t found = 0;
  for (const ShapeDesc& shape : s.shapes)
    for (const Expect& e : expected) {
      if (!shape.name.ends_with(e.mesh)) continue;
      ++found;
      const MaterialDesc& m = s.materials[size_t(shape.material)];
      ASSERT_TRUE(m.albedoTexture) << shape.name;
      EXPECT_THAT(m.albedoTexture->image->name, HasSubstr(e.image)) << shape.name << " has material " << m.name;
      EXPECT_NEAR(m.albedoTexture->transform.rotation, e.rotation, 1e-6) << shape.name;
      EXPECT_NEAR(m.albedoTexture->transform.scale.x, e.scale, 1e-6) << shape.name;
    }
  EXPECT_GE(found, expected.size()) << "shape names changed?";
  const auto box = std::find_if(s.shapes.begin(), s.shapes.end(), [](const ShapeDesc& x) { return x.name.find("textured box") != std::string::npos; });
  ASSERT_NE(box, s.shapes.end());
  ASSERT_TRUE(s.materials[size_t(box->material)].albedoTexture);
  EXPECT_THAT(s.materials[size_t(box->material)].albedoTexture->image->name, HasSubstr("BoxTextured.gltf images[0]"));  // CesiumLogoFlat.png
}

/// First-shot against NEE on scenes/gltf-samples.json at its defaults (tests/shipped_first_shot.h).
TEST(SceneAssets, PublicGltfSamplesFirstShotAgreesWithNee) {
  FIRSTSHOT_STATISTICS_ONLY("SceneAssets.PublicGltfSamplesKeepTheirMaterials");
  test::expectShippedSceneFirstShotAgreesWithNee("gltf-samples");
}

TEST(SceneAssets, MeshWithoutMaterialChecksItsKeys) {
  const std::string dir = test::tempDir();
  const std::string asset = test::source("scenes/assets/crate.gltf");
  const std::string scene = dir + "/scene.json";
  test::writeText(scene, R"({"materials": {}, "shapes": [{"type": "mesh", "file": ")" + asset +
                             R"(", "albedo": 0.5}], "lights": [{"type": "point", "position": [0, 2, 0], "power": 1}]})");
  try {
    loadScene(scene);
    FAIL() << "an unknown key was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("shapes[0]"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("albedo"));
  }
}

TEST(SceneAssets, SceneWithoutLightsSaysSo) {
  const std::string dir = test::tempDir();
  const auto r = test::run(std::string(FIRSTSHOT_RENDER_EXE) + " " + test::source("scenes/assets/crate.gltf") +
                           " --width 8 --height 6 --spp 1 -q -o " + dir + "/a.exr");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no lights, no emissive surfaces, no sky"));
  const auto lit = test::run(std::string(FIRSTSHOT_RENDER_EXE) + " " + test::source("scenes/gltf-crates.json") +
                             " --width 8 --height 6 --spp 1 -q -o " + dir + "/b.exr");
  EXPECT_EQ(lit.exitCode, 0) << lit.output;
  EXPECT_THAT(lit.output, ::testing::Not(HasSubstr("no lights")));
}

}  // namespace
}  // namespace firstshot
