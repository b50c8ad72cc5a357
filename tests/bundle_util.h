#pragma once
/// @file bundle_util.h
/// Helpers for the ray-bundle tests. Successive iterations of stochastic iteration are correlated
/// (each reflects the previous one's state), so the standard error of a mean over iterations is
/// taken from batch means: the K values are cut into consecutive batches, long against the
/// correlation length (≈ 1/(1−ρ) iterations), and the spread of the batch means gives σ.
#include <cmath>
#include <memory>
#include <vector>

#include "render/scene/camera.h"
#include "render/output/film.h"
#include "render/integrators/bundle/integrator.h"
#include "render/loop/renderer.h"

namespace firstshot::test {

/// Mean of a series and its standard error by @p batches batch means.
struct BatchMean {
  double mean = 0, se = 0;
};
inline BatchMean batchMean(const std::vector<double>& x, int batches = 8) {
  BatchMean r;
  const size_t n = x.size(), len = n / size_t(batches);
  for (double v : x) r.mean += v;
  r.mean /= double(n);
  std::vector<double> m(size_t(batches), 0.0);
  for (int b = 0; b < batches; ++b) {
    for (size_t i = 0; i < len; ++i) m[size_t(b)] += x[size_t(b) * len + i];
    m[size_t(b)] /= double(len);
  }
  double mm = 0, v = 0;
  for (double b : m) mm += b;
  mm /= batches;
  for (double b : m) v += (b - mm) * (b - mm);
  r.se = std::sqrt(v / double(batches - 1) / double(batches));
  return r;
}

/// Expected mean over iterations 0..K−1 of a quantity whose iteration-k expectation is
/// limit·(1 − ρ^{k+1}) (a closed enclosure of albedo ρ, starting from no incoming light):
/// limit·(1 − ρ(1 − ρ^K)/(K(1 − ρ))).
inline double startupMean(double limit, double rho, int K) {
  return limit * (1.0 - rho * (1.0 - std::pow(rho, K)) / (double(K) * (1.0 - rho)));
}

/// A bundle integrator preprocessed for @p scene.
inline std::unique_ptr<BundleIntegrator> makeBundle(const RenderScene& scene, const IntegratorOptions& io,
                                                    int resolution = 128) {
  auto b = std::make_unique<BundleIntegrator>(io);
  BundleSettings s;
  s.resolution = resolution;
  b->setSettings(s);
  b->preprocess(scene);
  return b;
}

/// The image estimate of every iteration 0..K−1 (one film each, 1 sample per pixel) as
/// per-pixel channel @p c values: images[k][pixel]. @p film receives the running mean (all K).
inline std::vector<std::vector<double>> iterationImages(const BundleIntegrator& b, const Camera& camera, int K, int c,
                                                        Film& film, uint64_t seed = 1, int threads = 0) {
  std::vector<std::vector<double>> images;
  for (int k = 0; k < K; ++k) {
    Film one(camera.width(), camera.height());
    RenderOptions ro;
    ro.spp = 1;
    ro.firstSample = k;
    ro.seed = seed;
    ro.threads = threads;
    render(b, camera, one, ro);
    std::vector<double> img(size_t(camera.width()) * size_t(camera.height()));
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x) {
        const Vec3d m = one.mean(x, y);
        img[size_t(y) * size_t(camera.width()) + size_t(x)] = m[c];
        film.add(x, y, Color(m), Color(0.0f), Vec3(0.0f));
      }
    images.push_back(std::move(img));
  }
  return images;
}

/// Per iteration: the mean of images[k] over the pixels of the block [x0, x1) × [y0, y1).
inline std::vector<double> blockSeries(const std::vector<std::vector<double>>& images, int width, int x0, int y0, int x1,
                                       int y1) {
  std::vector<double> s;
  for (const auto& img : images) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) sum += img[size_t(y) * size_t(width) + size_t(x)];
    s.push_back(sum / double((x1 - x0) * (y1 - y0)));
  }
  return s;
}

}  // namespace firstshot::test
