// Item buffers reduced on the GPU (preprocess/gl/gl_reduce.h) against the CPU reduction: the same
// scene preprocessed with glReduce "cpu" and "gpu" gives the same table within float rounding.
//
// Tolerance: the GPU sums fixed-point weights (w · 2^k, k such that a window's total stays below 2^61) where
// the CPU sums the doubles, so each sum differs by at most 2^-k per pixel, about 1e-18 of the window's total,
// and the fractions (visible / expected) by ~1e-15 relative. The factors are floats: equal or one rounding
// apart. We allow 4 float ulps (2^-21 relative), and nothing else may differ (same patches, same samples).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "preprocess/gl/gl_context.h"
#include "preprocess/preprocessor.h"
#include "preprocess/profile.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

// Profile counters on (read once, before main): they tell whether the GPU reduction ran.
const bool kProfiling = (setenv("FIRSTSHOT_PROFILE", "1", 1), true);

/// Why GL compute is unavailable here, or empty (GL 4.5 core, which includes 4.3 compute shaders and
/// fp64, is what every GLContext has).
std::string glUnavailable() {
  try {
    GLContext context(GLBackend::OSMesa);
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

FirstShotTable preprocess(const SceneDesc& s, int R, const std::string& reduce, const std::string& estimator) {
  PreprocessOptions o = defaultOptions(s);
  o.settings.resolution = R;
  o.settings.backend = "gl";
  o.settings.estimator = estimator;
  o.settings.minPatchSize = o.settings.patchSize;  // one mesh for both (no refinement decided on a rounding)
  o.threads = 2;
  o.quiet = true;
  o.glReduce = reduce;
  return preprocessScene(s, o);
}

/// Preprocesses @p s both ways (checking through the profile counters that the GPU reduction ran only in the
/// second) and compares the tables factor by factor.
void expectSameTable(const SceneDesc& s, int R, const std::string& estimator) {
  const int64_t gpuBefore = profile::total(profile::GpuReduce);
  const FirstShotTable cpu = preprocess(s, R, "cpu", estimator);
  ASSERT_EQ(profile::total(profile::GpuReduce), gpuBefore) << "the cpu reduction ran on the GPU";
  const FirstShotTable gpu = preprocess(s, R, "gpu", estimator);
  ASSERT_GT(profile::total(profile::GpuReduce), gpuBefore) << "the gpu reduction did not run";
  ASSERT_EQ(cpu.mesh.size(), gpu.mesh.size());
  ASSERT_EQ(cpu.rowStart, gpu.rowStart);
  ASSERT_EQ(cpu.sampleIndex, gpu.sampleIndex);
  ASSERT_EQ(cpu.factor.size(), gpu.factor.size());
  size_t differ = 0, bad = 0;
  for (size_t k = 0; k < cpu.factor.size(); ++k) {
    const float a = cpu.factor[k], b = gpu.factor[k];
    differ += a != b;
    if (std::abs(a - b) > std::ldexp(std::max(std::abs(a), std::abs(b)), -21) && bad++ < 5)
      ADD_FAILURE() << "factor " << k << ": cpu " << a << ", gpu " << b;
  }
  EXPECT_EQ(bad, 0u);
  std::printf("%zu factors, %zu differ by a rounding\n", cpu.factor.size(), differ);
}

#define SKIP_WITHOUT_GL()                                                      \
  if (const std::string why = glUnavailable(); !why.empty())                   \
    GTEST_SKIP() << "no OpenGL 4.3 compute here (OSMesa context failed): " << why;

// Cornell box: an area light at hemicube windows; the two blocks shade the floor and the walls (partly
// visible patches, decided by the occluder tests the shader does).
TEST(GLReduce, CornellAnalyticSameTableAsCpu) {
  SKIP_WITHOUT_GL();
  expectSameTable(loadScene(test::source("scenes/cornell.json")), 64, "analytic");
}

// The touched sums alone (plain pixel sums).
TEST(GLReduce, CornellPixelsSameTableAsCpu) {
  SKIP_WITHOUT_GL();
  expectSameTable(loadScene(test::source("scenes/cornell.json")), 64, "pixels");
}

// A point light (cube window) over a floor, half of it shadowed by a plate whose edge crosses a column of
// patches: every patch of that column is partly visible.
TEST(GLReduce, ShadowEdgeSameTableAsCpu) {
  SKIP_WITHOUT_GL();
  const SceneDesc s = test::sceneFromJson(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "quad", "material": "m", "vertices": [[-2,0.5,-2],[-2,0.5,2],[0.03,0.5,2],[0.03,0.5,-2]]}],
    "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}], "settings": {"patch_size": 0.1}})");
  expectSameTable(s, 256, "analytic");
}

// A scene with alpha cut-outs (the GL item buffers discard their holes) is reduced on the CPU even when "gpu" is
// asked for: a cut-out patch's coverage needs its alpha at each pixel centre, which the shader does not have.
TEST(GLReduce, CutoutSceneStaysOnTheCpu) {
  SKIP_WITHOUT_GL();
  const SceneDesc s = loadScene(test::source("scenes/cutout-screen.json"));
  const int64_t gpuBefore = profile::total(profile::GpuReduce);
  const FirstShotTable cpu = preprocess(s, 32, "cpu", "analytic");
  const FirstShotTable gpu = preprocess(s, 32, "gpu", "analytic");
  EXPECT_EQ(profile::total(profile::GpuReduce), gpuBefore) << "a cut-out scene was reduced on the GPU";
  EXPECT_EQ(cpu.factor, gpu.factor);
}

}  // namespace
