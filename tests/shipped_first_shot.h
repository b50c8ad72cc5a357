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

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "preprocess/preprocessor.h"
#include "render_util.h"
#include "test_util.h"

namespace firstshot::test {

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

/// Scene @p desc (named @p name) with its table by light tracing, BDPT and the irradiance cache against the path
/// tracer's NEE image without one (independent renders, 48 × 36): each image mean within 0.3% + 3σ of it, σ below
/// 0.3% of it (the emissive texture and cut-out screen scenes).
inline void expectTableIntegratorsAgreeWithNee(const std::string& name, SceneDesc desc) {
  desc.camera.width = 48, desc.camera.height = 36;
  const RenderScene plain(desc);
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = 128;
  po.quiet = true;
  const RenderScene tabled(desc, preprocessScene(desc, po));
  IntegratorOptions io;
  io.lightSampler = LightStrategy::All;
  double ref = 0, seRef = 0;
  imageMean(renderWith(*preprocessedIntegrator("path", io, plain), plain, 1024).film, 1, ref, seRef);
  for (const char* integrator : {"light", "bdpt", "irradiance-cache"}) {
    IntegratorOptions o = io;
    o.lightPathsPerPixel = std::string(integrator) == "light" ? 16 : 0;
    double mean = 0, se = 0;
    imageMean(renderWith(*preprocessedIntegrator(integrator, o, tabled), tabled, 256).film, 1, mean, se);
    const double s = std::hypot(se, seRef);
    fmt::print("{}, {} with the table: {:.5f} ± {:.5f} against NEE {:.5f} ± {:.5f}: {:+.3f}% ± {:.3f}%\n", name,
               integrator, mean, se, ref, seRef, 100 * (mean - ref) / ref, 100 * s / ref);
    EXPECT_LE(std::abs(mean - ref), 3 * s + 0.003 * ref) << integrator;
    EXPECT_LT(s, 0.003 * ref) << integrator << ": too noisy to test";
  }
}

}  // namespace firstshot::test
