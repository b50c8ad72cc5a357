#pragma once
/// @file hard_cases.h
/// Helpers for the hard-case suite (tests/hard_cases/*.json, docs/robustness.md): loading a case,
/// the tools' pipeline through the library (preprocess → .fsd file → read back → render with the
/// path tracer and the irradiance cache), and the checks every case shares: no NaN or Inf in the
/// table or the image.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <string>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "preprocess/preprocessor.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot::test {

/// Path of hard case @p file (e.g. "point_near_wall.json") in the source tree.
inline std::string hardCasePath(const std::string& file) { return source("tests/hard_cases/" + file); }

/// The scene of hard case @p file, loaded and validated like the tools do.
inline SceneDesc loadHardCase(const std::string& file) { return loadScene(hardCasePath(file)); }

/// The first-shot table of @p desc as the tools make it: Embree item buffers at R = 64 (the
/// scene's other settings), written to a .fsd file and read back against the scene's hash.
inline FirstShotTable hardCaseTable(const SceneDesc& desc) {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = 64;
  po.quiet = true;
  const std::string path = tempDir() + "/case.fsd";
  writeFirstShot(path, preprocessScene(desc, po));
  return readFirstShot(path, hashScene(desc));
}

/// Every factor and every patch's irradiance of @p t is finite and not negative.
inline void expectFiniteTable(const FirstShotTable& t) {
  ASSERT_EQ(t.rowStart.size(), size_t(t.mesh.size()) + 1);
  for (size_t k = 0; k < t.factor.size(); ++k)
    ASSERT_TRUE(std::isfinite(t.factor[k]) && t.factor[k] >= 0) << "factor " << k << " = " << t.factor[k];
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const Color E = t.irradiance(j);
    ASSERT_TRUE(std::isfinite(E.x) && std::isfinite(E.y) && std::isfinite(E.z)) << "patch " << j;
  }
}

/// No sample of @p run was NaN or Inf and every pixel mean is finite.
inline void expectFiniteImage(const RenderRun& run) {
  EXPECT_EQ(run.stats.nonFinite, 0u);
  for (int y = 0; y < run.film.height(); ++y)
    for (int x = 0; x < run.film.width(); ++x) ASSERT_TRUE(isFinite(run.film.mean(x, y))) << "pixel " << x << ", " << y;
}

/// The integrators every case renders with: the default path tracer and the irradiance cache.
inline const char* const kHardCaseIntegrators[] = {"path", "irradiance-cache"};

/// The integrator options the renderer takes from the scene (max_depth), defaults otherwise.
inline IntegratorOptions sceneOptions(const SceneDesc& desc) {
  IntegratorOptions io;
  io.maxDepth = desc.settings.maxDepth;
  return io;
}

/// Renders @p scene with integrator @p name (makeIntegrator) at @p spp.
inline RenderRun renderNamed(const std::string& name, const RenderScene& scene, const IntegratorOptions& io, int spp,
                             uint64_t seed = 1) {
  auto integrator = makeIntegrator(name, io);
  integrator->preprocess(scene);
  return renderWith(*integrator, scene, spp, seed);
}

/// Image mean of channel @p c and its standard error.
struct MeanSe {
  double mean = 0, se = 0;
};
inline MeanSe channelMean(const Film& film, int c) {
  MeanSe m;
  imageMean(film, c, m.mean, m.se);
  return m;
}

}  // namespace firstshot::test
