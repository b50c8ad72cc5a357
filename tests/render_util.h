#pragma once
/// @file render_util.h
/// Helpers for the renderer tests: scenes from JSON text, rendering into a Film, analytic
/// first-shot tables for a point light that sees every patch whole, and statistical comparison of
/// an image against per-pixel expectations with standard errors computed from the samples.
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/formats/json/scene_json.h"
#include "common/lights/form_factors.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "render/integrators/integrator.h"
#include "render/loop/renderer.h"
#include "render/output/film.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"

namespace firstshot::test {

/// Parses and validates a scene given as JSON text.
inline SceneDesc sceneFromJson(const std::string& text) {
  SceneDesc s = parseSceneJson(text, "test.json");
  validateScene(s);
  return s;
}

/// Expects each component of @p a within @p tolerance of @p b's.
inline void expectNear(const Vec3& a, const Vec3& b, float tolerance, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tolerance) << what;
  EXPECT_NEAR(a.y, b.y, tolerance) << what;
  EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

struct RenderRun {
  Film film;
  RenderStats stats;
};

/// Renders @p scene's camera view with @p integrator, already preprocessed for it, as @p ro says.
inline RenderRun renderWith(const Integrator& integrator, const RenderScene& scene, const RenderOptions& ro) {
  const Camera camera(scene.desc().camera);
  RenderRun run{Film(camera.width(), camera.height()), {}};
  run.stats = render(integrator, camera, run.film, ro);
  return run;
}

/// The same at @p spp samples per pixel, seed @p seed, on @p threads threads (0: one per core).
inline RenderRun renderWith(const Integrator& integrator, const RenderScene& scene, int spp, uint64_t seed = 1,
                            int threads = 0) {
  RenderOptions ro;
  ro.spp = spp;
  ro.seed = seed;
  ro.threads = threads;
  return renderWith(integrator, scene, ro);
}

/// Renders @p scene with the path integrator.
inline RenderRun renderPath(const RenderScene& scene, const IntegratorOptions& io, int spp, uint64_t seed = 1,
                            int threads = 0) {
  auto integrator = makeIntegrator("path", io);
  integrator->preprocess(scene);
  return renderWith(*integrator, scene, spp, seed, threads);
}

/// An integrating sphere: a point light of power @p phi (W) at (0.3, 0.25, −0.1) inside a closed,
/// tessellated unit sphere of albedo @p rho (inward normals), patch size 0.3; camera at the centre.
inline std::string integratingSphereScene(double rho, double phi) {
  return fmt::format(R"({{
    "camera": {{"position": [0, 0, 0], "look_at": [0.3, -0.2, -1], "fov_y": 80, "resolution": [32, 32]}},
    "materials": {{"wall": {{"type": "diffuse", "albedo": {}}}}},
    "shapes": [{{"type": "sphere", "material": "wall", "center": [0, 0, 0], "radius": 1, "subdivisions": 3, "flip_normals": true}}],
    "lights": [{{"type": "point", "position": [0.3, 0.25, -0.1], "power": {}}}],
    "settings": {{"patch_size": 0.3}}}})", rho, phi);
}

/// A first-shot table for point light @p light of @p scene over @p mesh, with the exact factors
/// r_j = Ω_j / (4π A_j) (REFERENCE.md), Ω_j the solid angle of patch j seen from the light. Valid
/// only when the light sees every patch whole (no occluders), e.g. over a plane or inside a
/// convex room.
inline FirstShotTable pointLightTable(const SceneDesc& scene, PatchMesh mesh, uint32_t light) {
  const LightDesc& l = scene.lights[light];
  FirstShotTable t;
  t.sceneHash = hashScene(scene);
  LightSample s;
  s.kind = LightSampleKind::Point;
  s.light = light;
  s.position = Vec3(l.position);
  s.emission = l.power;
  t.samples.push_back(s);
  t.replacedLights = {light};
  t.rowStart.push_back(0);
  for (const Patch& p : mesh.patches) {
    std::vector<Vec3d> poly;
    for (uint32_t k = 0; k < p.count; ++k) poly.emplace_back(p.v[k]);
    const double omega = analytic::solidAnglePolygon(l.position, poly);
    const double area = p.area;
    if (omega > 0 && area > 0) {
      t.sampleIndex.push_back(0);
      t.factor.push_back(static_cast<float>(omega / (4.0 * kPi * area)));
    }
    t.rowStart.push_back(t.factor.size());
  }
  t.mesh = std::move(mesh);
  return t;
}

/// Average of f over the footprint of pixel (x, y): an n×n grid of sub-pixel rays (midpoint rule).
inline double footprintAverage(const Camera& camera, int x, int y, const std::function<double(const Ray&)>& f, int n = 8) {
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sum += f(camera.generateRay(float(x) + (i + 0.5f) / float(n), float(y) + (j + 0.5f) / float(n)));
  return sum / double(n * n);
}

/// Result of comparing channel @p c of an image with expectations.
struct Comparison {
  double meanDiff = 0;     ///< mean over pixels of (pixel mean − expected)
  double se = 0;           ///< its standard error, from the per-pixel sample variances
  double meanExpected = 0; ///< mean of the expectations
  double worstBlockZ = 0;  ///< largest |block mean difference| / (block standard error + slack)
  double maxAbsDiff = 0;   ///< largest |pixel mean − expected|
};

/// Compares channel @p c of @p film with @p expected (one value per pixel, row-major). The whole
/// image and every @p block × @p block block of pixels are tested: a block's z value is
/// |mean difference| / (standard error + @p slack), where @p slack (≥ 0) is an allowed bias per pixel.
inline Comparison compareImage(const Film& film, const std::vector<double>& expected, int c, int block, double slack = 0) {
  Comparison r;
  const int w = film.width(), h = film.height();
  double varSum = 0;
  for (int by = 0; by < h; by += block)
    for (int bx = 0; bx < w; bx += block) {
      double d = 0, v = 0;
      int n = 0;
      for (int y = by; y < std::min(by + block, h); ++y)
        for (int x = bx; x < std::min(bx + block, w); ++x) {
          const double diff = film.mean(x, y)[c] - expected[size_t(y) * w + x];
          d += diff;
          v += film.variance(x, y)[c] / film.samples(x, y);
          ++n;
          r.maxAbsDiff = std::max(r.maxAbsDiff, std::abs(diff));
          r.meanExpected += expected[size_t(y) * w + x];
        }
      r.meanDiff += d;
      varSum += v;
      const double z = std::abs(d / n) / (std::sqrt(v) / n + slack);
      r.worstBlockZ = std::max(r.worstBlockZ, z);
    }
  const double N = double(w) * h;
  r.meanDiff /= N;
  r.meanExpected /= N;
  r.se = std::sqrt(varSum) / N;
  return r;
}

/// Per-pixel mean and variance of the difference a − b of two integrators' estimates of channel
/// @p c on identical camera samples (each integrator gets its own copy of the same sampler), so
/// that noise common to both cancels and the variance of the difference is measured directly.
struct PairedDifference {
  int width = 0, height = 0, spp = 0;
  std::vector<double> mean, variance;  ///< per pixel, row-major
  /// Mean difference over the image and its standard error.
  double imageMean() const {
    double s = 0;
    for (double m : mean) s += m;
    return s / double(mean.size());
  }
  double imageStandardError() const {
    double v = 0;
    for (double x : variance) v += x / spp;
    return std::sqrt(v) / double(variance.size());
  }
  /// Root-mean-square per-pixel bias: sqrt(mean(d̄² − var/n)), the noise's share removed.
  double rmsBias() const {
    double s = 0;
    for (size_t i = 0; i < mean.size(); ++i) s += mean[i] * mean[i] - variance[i] / spp;
    return std::sqrt(std::max(0.0, s / double(mean.size())));
  }
};

inline PairedDifference renderPairedDifference(const Integrator& a, const Integrator& b, const Camera& camera, int spp,
                                               uint64_t seed, int c) {
  PairedDifference r;
  r.width = camera.width(), r.height = camera.height(), r.spp = spp;
  r.mean.assign(size_t(r.width) * r.height, 0.0);
  r.variance.assign(r.mean.size(), 0.0);
  tbb::parallel_for(0, r.height, [&](int y) {
    for (int x = 0; x < r.width; ++x) {
      const uint64_t pixel = uint64_t(y) * r.width + x;
      double sum = 0, sum2 = 0;
      for (int s = 0; s < spp; ++s) {
        Sampler sa(seed, pixel, uint64_t(s));
        const Vec2 j = sa.next2D();
        Sampler sb = sa;
        const Ray ray = camera.generateRay(float(x) + j.x, float(y) + j.y);
        const double d = double(a.Li(ray, sa)[c]) - double(b.Li(ray, sb)[c]);
        sum += d, sum2 += d * d;
      }
      const double m = sum / spp;
      r.mean[pixel] = m;
      r.variance[pixel] = spp > 1 ? std::max(0.0, (sum2 - spp * m * m) / (spp - 1)) : 0.0;
    }
  });
  return r;
}

/// Mean of channel @p c over the image and its standard error from the per-pixel sample variances.
inline void imageMean(const Film& film, int c, double& mean, double& se) {
  double sum = 0, var = 0;
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      sum += film.mean(x, y)[c];
      var += film.variance(x, y)[c] / film.samples(x, y);
    }
  const double N = double(film.width()) * film.height();
  mean = sum / N;
  se = std::sqrt(var) / N;
}

/// Mean over the pixels of the film's per-pixel means, channels averaged.
inline double greyImageMean(const Film& film) {
  double sum = 0;
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      const Vec3d m = film.mean(x, y);
      sum += (m.x + m.y + m.z) / 3.0;
    }
  return sum / (double(film.width()) * film.height());
}

/// The integrator @p name (makeIntegrator) with @p io, preprocessed for @p scene.
inline std::unique_ptr<Integrator> preprocessedIntegrator(const std::string& name, const IntegratorOptions& io,
                                                          const RenderScene& scene) {
  std::unique_ptr<Integrator> integrator = makeIntegrator(name, io);
  integrator->preprocess(scene);
  return integrator;
}

/// Expects path, light, bdpt and irradiance-cache (max depth 3, 2 spp, seed 1) to render @p scene
/// to the same image, bit for bit, on one thread and on two.
inline void expectSameImageForOneAndTwoThreads(const RenderScene& scene) {
  for (const char* name : {"path", "light", "bdpt", "irradiance-cache"}) {
    IntegratorOptions io;
    io.maxDepth = 3;
    const auto integrator = preprocessedIntegrator(name, io, scene);
    const auto one = renderWith(*integrator, scene, 2, 1, 1), two = renderWith(*integrator, scene, 2, 1, 2);
    for (int y = 0; y < one.film.height(); ++y)
      for (int x = 0; x < one.film.width(); ++x)
        ASSERT_EQ(one.film.mean(x, y), two.film.mean(x, y)) << name << " " << x << ", " << y;
  }
}

/// The grey image mean of renderWith(@p integrator, @p scene, @p spp, @p seed), expecting no non-finite sample.
inline double renderedGreyMean(const Integrator& integrator, const RenderScene& scene, int spp, uint64_t seed,
                               const std::string& what) {
  const RenderRun run = renderWith(integrator, scene, spp, seed);
  EXPECT_EQ(run.stats.nonFinite, 0u) << what;
  return greyImageMean(run.film);
}

/// A mean over independent repetitions and its standard error.
struct Estimate {
  double mean = 0, se = 0;
};

}  // namespace firstshot::test
