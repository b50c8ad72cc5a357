#pragma once
/// @file light_tracing_util.h
/// Helpers for the light-tracing tests: running moments, and light subpaths traced in parallel
/// with one sampler per particle (so results do not depend on the threads).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "render/integrators/common/light_path.h"
#include "render/integrators/light/integrator.h"

namespace firstshot::test {

/// Sample mean and standard error of a stream of values.
struct Moments {
  double n = 0, sum = 0, sum2 = 0;
  void add(double x) { n += 1, sum += x, sum2 += x * x; }
  void merge(const Moments& o) { n += o.n, sum += o.sum, sum2 += o.sum2; }
  double mean() const { return n > 0 ? sum / n : 0.0; }
  /// Standard error of the mean.
  double se() const {
    if (n < 2) return 0;
    const double m = mean();
    return std::sqrt(std::max(0.0, (sum2 / n - m * m) / (n - 1)));
  }
};

/// Mean of the three channels.
inline double gray(const Color& c) { return (double(c.x) + c.y + c.z) / 3.0; }

/// Traces particles 0..n−1 of @p lt's light (Sampler(seed, i, 0, kParticleStream)) and calls
/// @p visit(i, path) for each (paths that emitted nothing are visited empty). @p visit runs
/// concurrently for different particles of different blocks; blocks of particles are fixed.
inline void forEachLightPath(const RenderScene& scene, const LightTracingIntegrator& lt, uint64_t n, uint64_t seed,
                             const std::function<void(uint64_t, const std::vector<LightVertex>&)>& visit) {
  const uint64_t block = 4096;
  tbb::parallel_for(uint64_t(0), (n + block - 1) / block, [&](uint64_t b) {
    std::vector<LightVertex> path;
    uint64_t rays = 0;
    for (uint64_t i = b * block; i < std::min(n, (b + 1) * block); ++i) {
      Sampler sampler(seed, i, 0, LightTracingIntegrator::kParticleStream);
      if (!traceLightPath(scene, lt.particleEmitters(), lt.pathOptions(), sampler, path, rays)) path.clear();
      visit(i, path);
    }
  });
}

}  // namespace firstshot::test
