// A JSON scene that places a public asset with its own materials (a mesh shape without "material"), and the
// line a scene without any light prints (issue 34: scenes users bring).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "common/error.h"
#include "common/scene_desc.h"
#include "common/texture.h"
#include "tests/test_util.h"

namespace fs {
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
}  // namespace fs
