// The two-pass fill's batches: each task of a batch traces against the cache as the batch found it, so records that
// two tasks of one batch both need are made twice and one is dropped at the merge. The first pixels' records make the
// deeper levels' records all over the room; batches that grew regardless (1, 2, 4, ...) made those once a task. The
// batches grow only while few records are made twice, and not after a batch whose pixels all saw nothing: a camera
// whose first rows see nothing and the Cornell box seen whole both make each record about once.
// (That the batches, like the records, do not depend on the threads: test_irradiance_cache_file.cpp's images.)
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "common/formats/load_scene.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/irradiance_cache_util.h"

using namespace firstshot;

namespace {

IrradianceCacheStats filled(const SceneDesc& desc) {
  const RenderScene scene(desc);
  IrradianceCacheSettings s;
  s.quiet = true;
  IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  ic.preprocess(scene);
  return ic.stats();
}

}  // namespace

TEST(IrradianceCacheBatches, EachRecordIsMadeAboutOnce) {
  SceneDesc whole = loadScene(test::source("scenes/cornell.json"));
  whole.camera.width = whole.camera.height = 64;
  SceneDesc above = whole;  // the top half of the picture sees over the box: the first 8 pixels filled miss it
  above.camera.lookAt.y += 0.4;
  for (const SceneDesc* desc : {&whole, &above}) {
    const IrradianceCacheStats s = filled(*desc);
    fmt::print("{}: {} records made, {} of them twice, {} kept; {} rays\n", desc == &whole ? "whole" : "above",
               s.fillMade, s.fillDuplicates, s.records, s.fillRays);
    ASSERT_GT(s.records, 500u);
    EXPECT_LE(s.fillDuplicates, s.fillMade / 3);
  }
}
