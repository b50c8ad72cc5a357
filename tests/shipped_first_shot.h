#pragma once
/// @file shipped_first_shot.h
/// First-shot against NEE on a shipped scene (tests/test_thin_glass_render.cpp, test_cutout.cpp,
/// test_daylight_factor.cpp): the path tracer with and without the scene's table (Embree item buffers unless
/// @p backend says otherwise, R = 128) at
/// 48 × 36, every light sampled at every vertex, on the same camera samples (256 spp, 5 batches); the image mean of
/// the difference within 0.3% + 3σ of the NEE image's mean, and σ below 0.2% of it (sharp enough to mean something).
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/scene_desc.h"
#include "preprocess/preprocessor.h"
#include "render_util.h"
#include "test_util.h"

namespace fs::test {

inline void expectShippedSceneFirstShotAgreesWithNee(const std::string& name, const std::string& backend = "embree") {
  SceneDesc desc = loadScene(source("scenes/" + name + ".json"));
  desc.camera.width = 48, desc.camera.height = 36;
  const RenderScene plain(desc);
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = backend;
  po.settings.resolution = 128;
  po.quiet = true;
  const RenderScene tabled(desc, preprocessScene(desc, po));
  IntegratorOptions io;
  io.lightSampler = LightStrategy::All;  // the same NEE at the first vertex: the difference is the table's
  auto nee = preprocessedIntegrator("path", io, plain);
  auto firstShot = preprocessedIntegrator("path", io, tabled);
  double mean = 0, seMean = 0;
  imageMean(renderWith(*nee, plain, 64).film, 1, mean, seMean);
  const PairedDifference d = renderPairedDifference(*firstShot, *nee, Camera(desc.camera), 256, 5, 1);
  const double diff = d.imageMean(), se = d.imageStandardError();
  fmt::print("{} ({}): NEE {:.5f} ± {:.5f}; first-shot − NEE {:+.3f}% ± {:.3f}%\n", name, backend, mean, seMean, 100 * diff / mean,
             100 * se / mean);
  EXPECT_GT(mean, 0.0);
  EXPECT_LE(std::abs(diff), 3 * se + 0.003 * mean);
  EXPECT_LT(se, 0.002 * mean);  // sharp enough to mean something
}

}  // namespace fs::test
