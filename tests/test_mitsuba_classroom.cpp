// A public Mitsuba 0.6 scene as it ships (../shared/scenes/classroom, NovaZeeke's "Japanese Classroom" in Bitterli's
// Mitsuba version, lit by a sunsky through its windows): it loads with its sun and sky; and (DISABLED_, about two
// minutes on two cores: run with --gtest_also_run_disabled_tests) the tools preprocess and render it, the image finite
// with a positive mean. Skipped, saying so, where ../shared/scenes is absent.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/scene_desc.h"
#include "common/sky_desc.h"
#include "render/output/image_io.h"
#include "tests/test_util.h"

using namespace fs;

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

TEST(MitsubaClassroom, DISABLED_PreprocessesAndRenders) {
  const std::string scene = test::source(kScene);
  if (!std::filesystem::exists(scene)) GTEST_SKIP() << scene << " is absent (the public scenes live in ../shared/scenes)";
  // The tools at their defaults, but for a coarse patch size and a tiny image with one pass of the path tracer, so
  // that the test stays short.
  const std::string dir = test::tempDir();
  const auto pre = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " '" + scene + "' --patch-size 0.5 -o " + dir +
                             "/c.fsd 2>&1");
  ASSERT_EQ(pre.exitCode, 0) << pre.output;
  const auto render = test::run(std::string(FIRSTSHOT_RENDER_EXE) + " '" + scene + "' --firstshot " + dir +
                                "/c.fsd --integrator path --width 32 --height 18 --spp 1 -o " + dir + "/c.exr 2>&1");
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
