#pragma once
/// @file irradiance_cache_util.h
/// Helpers for the irradiance cache tests: the Cornell box with a point light (noise-free direct
/// light, so that what remains is the cache's own error), and the error of an integrator against
/// a path-traced reference on the same camera rays.
///
/// The paired estimate: for every pixel and sample k the camera ray is the renderer's (seed,
/// pixel, k) ray; the integrator's estimate minus the mean of @c pathPerRay path-traced estimates
/// along the very same ray is d_k. Pixel aliasing cancels in d, so the per-pixel mean of d² minus
/// its sampling variance / n is an unbiased estimate of the squared bias of that pixel. The
/// relative RMSE is √(mean of those over pixels and channels) / mean of the reference.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "render/scene/camera.h"
#include "render/integrators/integrator.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot::test {

/// scenes/cornell.json at @p size² pixels with its area light replaced by a 3 W point light
/// (the light quad stays as a black patch).
inline SceneDesc cornellWithPointLight(int size) {
  SceneDesc desc = loadScene(source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = size;
  for (MaterialDesc& m : desc.materials) m.emission = Color(0.0f);
  LightDesc l;
  l.name = "point";
  l.type = LightType::Point;
  l.position = Vec3d(0.15, 0.42, 0.38);
  l.power = Color(3.0f);
  desc.lights = {l};
  return desc;
}

/// Path-traced reference radiance along the renderer's camera rays.
struct PairedReference {
  int width = 0, height = 0, spp = 0;
  uint64_t seed = 0;
  std::vector<Vec3d> L;  ///< per pixel and sample: mean of the path-traced estimates
  double mean = 0;       ///< over pixels, samples and channels
};

inline PairedReference pairedReference(const Integrator& path, const Camera& camera, int spp, int pathPerRay, uint64_t seed) {
  PairedReference r;
  r.width = camera.width(), r.height = camera.height(), r.spp = spp, r.seed = seed;
  const size_t pixels = size_t(r.width) * size_t(r.height);
  r.L.assign(pixels * size_t(spp), Vec3d(0.0));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t p = range.begin(); p < range.end(); ++p)
      for (int k = 0; k < spp; ++k) {
        Sampler cam(seed, p, uint64_t(k));
        const Vec2 j = cam.next2D();
        const Ray ray = camera.generateRay(float(p % size_t(r.width)) + j.x, float(p / size_t(r.width)) + j.y);
        Vec3d sum(0.0);
        for (int q = 0; q < pathPerRay; ++q) {
          Sampler s(seed ^ 0x5eed, p, uint64_t(k) * uint64_t(pathPerRay) + uint64_t(q));
          s.next2D();
          sum += Vec3d(path.Li(ray, s));
        }
        r.L[p * size_t(spp) + size_t(k)] = sum / double(pathPerRay);
      }
  });
  double m = 0;
  for (const Vec3d& v : r.L) m += v.x + v.y + v.z;
  r.mean = m / (3.0 * double(r.L.size()));
  return r;
}

/// Error of an integrator against a paired reference.
struct PairedError {
  double relRmse = 0;    ///< √(mean of the per-pixel squared-bias estimates) / mean of the reference
  double meanDiff = 0;   ///< (mean of the estimates − mean of the reference) / mean of the reference
  double meanDiffSe = 0; ///< its standard error
};

/// The error of @p integrator against @p ref (see the file comment). Along each ray the estimate is
/// the mean of @p perRay evaluations: the renderer's own (same random numbers) and perRay − 1
/// with others, which lowers the integrator's own noise (e.g. of glossy reflections).
inline PairedError pairedError(const Integrator& integrator, const Camera& camera, const PairedReference& ref, int perRay = 1) {
  const size_t pixels = size_t(ref.width) * size_t(ref.height);
  std::vector<double> bias2(pixels, 0.0), pixelMean(pixels, 0.0), pixelVar(pixels, 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t p = range.begin(); p < range.end(); ++p) {
      Vec3d sum(0.0), sum2(0.0);
      double sumC = 0, sumC2 = 0;  // of the channel mean of d
      for (int k = 0; k < ref.spp; ++k) {
        Sampler s(ref.seed, p, uint64_t(k));
        const Vec2 j = s.next2D();
        const Ray ray = camera.generateRay(float(p % size_t(ref.width)) + j.x, float(p / size_t(ref.width)) + j.y);
        Vec3d L(integrator.Li(ray, s));
        for (int q = 1; q < perRay; ++q) {
          Sampler t(ref.seed ^ 0x1c, p, uint64_t(k) * uint64_t(perRay) + uint64_t(q));
          t.next2D();
          L += Vec3d(integrator.Li(ray, t));
        }
        const Vec3d d = L / double(perRay) - ref.L[p * size_t(ref.spp) + size_t(k)];
        sum += d;
        sum2 += d * d;
        const double c = (d.x + d.y + d.z) / 3.0;
        sumC += c;
        sumC2 += c * c;
      }
      const double n = ref.spp;
      const Vec3d m = sum / n, var = (sum2 - n * m * m) / (n - 1);
      bias2[p] = (m.x * m.x + m.y * m.y + m.z * m.z) - (var.x + var.y + var.z) / n;
      pixelMean[p] = sumC / n;
      pixelVar[p] = (sumC2 - n * pixelMean[p] * pixelMean[p]) / (n - 1) / n;  // of pixelMean[p]
    }
  });
  double total = 0, m = 0, v = 0;
  for (size_t p = 0; p < pixels; ++p) total += bias2[p], m += pixelMean[p], v += pixelVar[p];
  PairedError e;
  e.relRmse = std::sqrt(std::max(0.0, total / (3.0 * double(pixels)))) / ref.mean;
  e.meanDiff = m / double(pixels) / ref.mean;
  e.meanDiffSe = std::sqrt(v) / double(pixels) / ref.mean;
  return e;
}

inline double pairedRelativeRmse(const Integrator& integrator, const Camera& camera, const PairedReference& ref) {
  return pairedError(integrator, camera, ref).relRmse;
}

/// Least-squares line y = c0 + c1·x and its r².
struct LineFit {
  double intercept = 0, slope = 0, r2 = 0;
};
inline LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = double(x.size());
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  LineFit f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0 ? sxy * sxy / (sxx * syy) : 0;
  return f;
}

}  // namespace firstshot::test
