// Bidirectional path tracing (--integrator bdpt): images against path tracing per 8×8 block on
// the shipped scenes and on a mirror-and-glass scene (σ from the per-pass block means).
#include <gtest/gtest.h>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/bdpt/integrator.h"
#include "tests/block_compare.h"
#include "tests/test_util.h"

using namespace firstshot;

TEST(Bdpt, CornellImageAgreesWithPathTracing) { test::expectAgreesWithPathTracing("bdpt", "cornell", 200, 300); }
TEST(Bdpt, ManyLightsImageAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("Bdpt.MixedLightsAgreeWithPathTracing");
  test::expectAgreesWithPathTracing("bdpt", "many-lights", 200, 300);
}
TEST(Bdpt, SierpinskiGlossyImageAgreesWithPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("Bdpt.MixedLightsAgreeWithPathTracing");
  test::expectAgreesWithPathTracing("bdpt", "sierpinski-glossy", 200, 300);
}

// Delta surfaces seen by the camera and met by both subpaths: no connection through them, their
// densities cancel in the MIS weights; the glass's caustic comes from the t = 1 and s = 0 strategies.
TEST(Bdpt, MirrorAndGlassAgreeWithPathTracing) { test::expectAgreesWithPathTracing("bdpt", "mirror-glass", test::mirrorGlassScene(), 200, 300); }

// Every kind of light at once, on an open scene: a directional light (s = 1 and light subpaths
// from its disk), a spot, a point light and an area light, over diffuse and glossy surfaces.
TEST(Bdpt, MixedLightsAgreeWithPathTracing) {
  test::expectAgreesWithPathTracing("bdpt", "mixed-lights", test::mixedLightsScene(), 200, 300);
}

// With a first-shot table and --shoot-firstshot off, BDPT shoots and samples the table's small
// lights like all others (the table is ignored): the same image as without a table.
// The cases mirror test_light_tracing.cpp's, one TEST each: their sample counts and reasons differ per integrator.
TEST(Bdpt, FirstShotOffLeavesTheImageUnchanged) {
  IntegratorOptions io;
  io.shootFromPatches = false;
  test::expectTableLeavesImageUnchanged("bdpt", 150, io);
}

// --max-depth counts bounces as the path tracer does (s + t − 2 ≤ D over every strategy).
TEST(Bdpt, MaxDepthCountsBouncesLikePathTracing) {
  SceneDesc d = loadScene(test::source("scenes/cornell.json"));
  d.settings.maxDepth = 2;
  test::expectAgreesWithPathTracing("bdpt", "cornell, max depth 2", d, 200, 300);
}
