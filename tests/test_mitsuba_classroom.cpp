// A public Mitsuba 0.6 scene as it ships (../shared/scenes/classroom, NovaZeeke's "Japanese Classroom" in Bitterli's
// Mitsuba version, lit by a sunsky through its windows): it loads with its sun and sky, and the tools preprocess and
// render it at their defaults, the image finite with a positive mean (not under the sanitizers: minutes there).
// Skipped, saying so, where ../shared/scenes is absent.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/scene/sky_desc.h"
#include "render/output/image_io.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {
const std::string kScene = "../shared/scenes/classroom/scene.xml";
}

TEST(MitsubaClassroom, Loads) {
  const std::string scene = test::source(kScene);
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << scene << " is absent (the public scenes live in ../shared/scenes)";
  const SceneDesc d = loadScene(scene);
  ASSERT_TRUE(d.sky) << "the sunsky's sky";
  ASSERT_EQ(d.lights.size(), 1u) << "the sunsky's sun";
  EXPECT_EQ(d.lights[0].type, LightType::Directional);
  EXPECT_GT(d.sky->dome.horizontalIlluminance(), 0.0);
  EXPECT_EQ(d.camera.width, 1280);
}

TEST(MitsubaClassroom, PreprocessesAndRendersAtTheDefaults) {
  const std::string scene = test::source(kScene);
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << scene << " is absent (the public scenes live in ../shared/scenes)";
#ifdef FIRSTSHOT_SANITIZED
  GTEST_SKIP() << "the whole classroom takes minutes under the sanitizers (the Release build runs it)";
#endif
  // The tools at their defaults (about 20 s of preprocessing, 1.4 GiB), then one pass of a small picture.
  const std::string dir = test::tempDir();
  const auto pre = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " '" + scene + "' --quiet -o " + dir + "/c.fsd 2>&1");
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
  const auto render = test::run(std::string(FIRSTSHOT_RENDER_EXE) + " '" + scene + "' --firstshot " + dir +
                                "/c.fsd --width 32 --height 18 --spp 1 --quiet -o " + dir + "/c.exr 2>&1");
  ASSERT_EQ(render.exitCode, 0) << render.output;
  const image::Image img = image::read(dir + "/c.exr");
  ASSERT_EQ(img.width, 32);
  double sum = 0;
  for (float v : img.data) {
    ASSERT_TRUE(std::isfinite(v));
    sum += v;
  }
  EXPECT_GT(sum / double(img.data.size()), 0.0);
}
