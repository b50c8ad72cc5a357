#pragma once
/// @file splat_checks.h
/// Checks every splatting integrator (light tracing, BDPT) passes: the same film for 1 and 2
/// threads and pass by pass, and its command line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/integrator.h"
#include "render/loop/renderer.h"
#include "render/output/film.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot::test {

/// Renders the Cornell box at 40×30 (1200 samples a pass: two splat chunks) with @p integrator
/// (a makeIntegrator name) at 3 spp on 1 and on 2 threads, and pass by pass: every pixel's mean and
/// variance must be bit-identical, and the image not black. @p withTable: with a first-shot table
/// (Embree, R = 64; the shooting integrators' table mode). Returns the one-thread run.
inline RenderRun expectSameFilmForThreadsAndPasses(const std::string& integrator, bool withTable = false) {
  SceneDesc d = loadScene(source("scenes/cornell.json"));
  d.camera.width = 40, d.camera.height = 30;
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene scene = withTable ? RenderScene(d, preprocessScene(d, po)) : RenderScene(d, d.settings.patchSize);
  auto it = makeIntegrator(integrator, IntegratorOptions());
  it->preprocess(scene);
  RenderRun one = renderWith(*it, scene, 3, 1, 1);
  const RenderRun two = renderWith(*it, scene, 3, 1, 2);
  const Camera camera(d.camera);
  Film passes(40, 30);
  for (int k = 0; k < 3; ++k) {
    RenderOptions ro;
    ro.spp = 1, ro.firstSample = k, ro.threads = 2;
    render(*it, camera, passes, ro);
  }
  double sum = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      EXPECT_EQ(one.film.mean(x, y), two.film.mean(x, y));
      EXPECT_EQ(one.film.variance(x, y), two.film.variance(x, y));
      EXPECT_EQ(one.film.mean(x, y), passes.mean(x, y));
      sum += one.film.mean(x, y).x;
    }
  EXPECT_GT(sum, 0.0);
  EXPECT_EQ(one.stats.spp, 3);
  return one;
}

/// `firstshot-render --integrator @p integrator` writes an EXR with AOVs and a PNG, renders with
/// --time, and refuses bad values (and the misspelt name @p misspelt) with exit code 2.
inline void expectCommandLine(const std::string& integrator, const std::string& misspelt) {
  const std::string exe = FIRSTSHOT_RENDER_EXE, scene = source("scenes/cornell.json"), dir = tempDir();
  const std::string it = " --integrator " + integrator;
  const auto ok = run(exe + " " + scene + it + " --spp 2 --width 24 --height 20 --aov -o " + dir + "/a.exr -o " + dir + "/a.png");
  ASSERT_EQ(ok.exitCode, 0) << ok.output;
  int w = 0, h = 0;
  std::vector<std::string> channels;
  Film::read(dir + "/a.exr", w, h, channels);
  EXPECT_EQ(channels.size(), 9u);
  EXPECT_EQ(w, 24);
  const auto timed = run(exe + " " + scene + it + " --time 0.2 --width 24 --height 20 -q -o " + dir + "/t.exr");
  EXPECT_EQ(timed.exitCode, 0) << timed.output;
  for (const std::string& bad : {it + " --spp 0", it + " --accuracy 0.2", it + " --max-depth -1", " --integrator " + misspelt}) {
    const auto r = run(exe + " " + scene + bad + " -q -o " + dir + "/bad.exr");
    EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.output;
  }
}

}  // namespace firstshot::test
