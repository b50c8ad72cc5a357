// Bidirectional path tracing (--integrator bdpt): images against path tracing per 8×8 block on
// the shipped scenes and on a mirror-and-glass scene (σ from the per-pass block means).
#include <gtest/gtest.h>

#include "preprocess/preprocessor.h"
#include "render/integrators/bdpt/integrator.h"
#include "tests/block_compare.h"
#include "tests/test_util.h"

using namespace fs;

TEST(Bdpt, CornellImageAgreesWithPathTracing) { test::expectAgreesWithPathTracing("bdpt", "cornell", 200, 300); }
TEST(Bdpt, ManyLightsImageAgreesWithPathTracing) { test::expectAgreesWithPathTracing("bdpt", "many-lights", 200, 300); }
TEST(Bdpt, SierpinskiGlossyImageAgreesWithPathTracing) { test::expectAgreesWithPathTracing("bdpt", "sierpinski-glossy", 200, 300); }

// Delta surfaces seen by the camera and met by both subpaths: no connection through them, their
// densities cancel in the MIS weights; the glass's caustic comes from the t = 1 and s = 0 strategies.
TEST(Bdpt, MirrorAndGlassAgreeWithPathTracing) { test::expectAgreesWithPathTracing("bdpt", "mirror-glass", test::mirrorGlassScene(), 200, 300); }

// Every kind of light at once, on an open scene: a directional light (s = 1 and light subpaths
// from its disk), a spot, a point light and an area light, over diffuse and glossy surfaces.
TEST(Bdpt, MixedLightsAgreeWithPathTracing) {
  test::expectAgreesWithPathTracing("bdpt", "mixed-lights", test::sceneFromJson(R"({"materials": {
      "white": {"type": "diffuse", "albedo": 0.6}, "gloss": {"type": "glossy", "albedo": 0.2, "specular": 0.5, "exponent": 10},
      "lamp": {"type": "diffuse", "emission": [4, 3, 2]}},
    "shapes": [{"type": "quad", "material": "white", "vertices": [[-3,0,-3],[-3,0,3],[1,0,3],[1,0,-3]]},
               {"type": "quad", "material": "gloss", "vertices": [[1,0,-3],[1,4,-3],[1,4,3],[1,0,3]]},
               {"type": "box", "material": "white", "min": [-0.5,0,-0.3], "max": [0.1,0.7,0.3]},
               {"type": "quad", "material": "lamp", "vertices": [[-1.2,1.5,-0.3],[-0.6,1.5,-0.3],[-0.6,1.5,0.3],[-1.2,1.5,0.3]]}],
    "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "irradiance": 1.5},
               {"type": "spot", "position": [0.5, 1.8, 0.5], "direction": [0, -1, 0], "power": 20,
                "inner_angle": 20, "outer_angle": 35},
               {"type": "point", "position": [-1, 1, 1], "power": 10}],
    "camera": {"position": [-1.2, 3.2, -2.2], "look_at": [0.2, 0, 0.3], "fov_y": 55, "resolution": [32, 24]},
    "settings": {"patch_size": 0.5, "max_depth": 6}})"), 200, 300);
}

// With a first-shot table BDPT shoots and samples the table's small lights like all others (the
// table is ignored): the same image as without a table.
TEST(Bdpt, FirstShotTableLeavesTheImageUnchanged) { test::expectTableLeavesImageUnchanged("bdpt", 150); }

// --max-depth counts bounces as the path tracer does (s + t − 2 ≤ D over every strategy).
TEST(Bdpt, MaxDepthCountsBouncesLikePathTracing) {
  SceneDesc d = loadScene(test::source("scenes/cornell.json"));
  d.settings.maxDepth = 2;
  test::expectAgreesWithPathTracing("bdpt", "cornell, max depth 2", d, 200, 300);
}
