// Bidirectional path tracing (--integrator bdpt): images against path tracing per 8×8 block on
// the shipped scenes and on a mirror-and-glass scene (σ from the per-pass block means).
#include <gtest/gtest.h>

#include "render/integrators/bdpt/integrator.h"
#include "tests/block_compare.h"
#include "tests/test_util.h"

using namespace fs;

namespace {

/// BDPT against path tracing on @p d at 32×24: every block within 3σ of the difference (blocks
/// showing lights included: strategy (0, 2) draws them).
void expectImagesAgree(const std::string& name, SceneDesc d, int bdptPasses, int ptPasses) {
  d.camera.width = 32, d.camera.height = 24;
  const RenderScene scene(d, d.settings.patchSize);
  IntegratorOptions io;
  io.maxDepth = d.settings.maxDepth;
  BdptIntegrator bdpt(io);
  auto pt = makeIntegrator("path", io);
  bdpt.preprocess(scene);
  pt->preprocess(scene);
  test::expectBlocksAgree(name, test::blockMeans(bdpt, scene, bdptPasses), test::blockMeans(*pt, scene, ptPasses));
}

void expectImagesAgree(const std::string& name, int bdptPasses, int ptPasses) {
  expectImagesAgree(name, loadScene(test::source("scenes/" + name + ".json")), bdptPasses, ptPasses);
}

}  // namespace

TEST(Bdpt, CornellImageAgreesWithPathTracing) { expectImagesAgree("cornell", 200, 300); }
TEST(Bdpt, ManyLightsImageAgreesWithPathTracing) { expectImagesAgree("many-lights", 200, 300); }
TEST(Bdpt, SierpinskiGlossyImageAgreesWithPathTracing) { expectImagesAgree("sierpinski-glossy", 200, 300); }

// Delta surfaces seen by the camera and met by both subpaths: no connection through them, their
// densities cancel in the MIS weights; the glass's caustic comes from the t = 1 and s = 0 strategies.
TEST(Bdpt, MirrorAndGlassAgreeWithPathTracing) { expectImagesAgree("mirror-glass", test::mirrorGlassScene(), 200, 300); }
