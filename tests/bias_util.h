#pragma once
/// @file bias_util.h
/// Helpers for measuring the bias of first-shot against NEE path tracing: the metre-scale Cornell
/// box, preprocessing at default settings, a paired image-mean difference with the pixels that see
/// an emitter left out, and a brute-force Monte Carlo check of each patch's table irradiance.
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/lights/emission_profile.h"
#include "common/table/firstshot.h"
#include "preprocess/preprocessor.h"
#include "render/firstshot/lighting.h"
#include "render/integrators/integrator.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"
#include "tests/test_util.h"

namespace firstshot::test {

/// The shipped scenes/cornell.json scaled ×10 (scenes/cornell-metre.json: a 5.56 m room, its light
/// 1 cm under the ceiling) at its own settings; the light tessellated at @p lightPatchSize, m, if given.
inline SceneDesc cornellMetre(double lightPatchSize = 0) {
  SceneDesc d = loadScene(source("scenes/cornell-metre.json"));
  if (lightPatchSize > 0) d.settings.lightPatchSize = lightPatchSize;
  return d;
}

/// The preprocessor at the scene's default settings, on back end @p backend.
inline FirstShotTable preprocessDefault(const SceneDesc& desc, const std::string& backend = "gl") {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = backend;
  po.quiet = true;
  return preprocessScene(desc, po);
}

/// Paired image-mean difference between two integrators (identical camera samples, same sampler
/// stream), averaged over the three channels. Camera samples whose primary ray meets an emitter
/// count zero in both (the light itself left out of the measure).
struct BiasMeasure {
  double reference = 0;  ///< image mean of b (NEE)
  double diff = 0;       ///< image mean of a − b
  double se = 0;         ///< standard error of diff, from the per-pixel sample variances
  double relative() const { return diff / reference; }
  double relativeSe() const { return se / reference; }
};

inline BiasMeasure measurePairedBias(const Integrator& a, const Integrator& b, const RenderScene& scene,
                                     const Camera& camera, int spp, uint64_t seed) {
  const int w = camera.width(), h = camera.height();
  std::vector<double> mean(size_t(w) * h), var(mean.size()), ref(mean.size());
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const uint64_t pixel = uint64_t(y) * w + x;
      double sum = 0, sum2 = 0, sumRef = 0;
      for (int s = 0; s < spp; ++s) {
        Sampler sa(seed, pixel, uint64_t(s));
        const Vec2 j = sa.next2D();
        Sampler sb = sa;
        const Ray ray = camera.generateRay(float(x) + j.x, float(y) + j.y);
        Hit hit;
        if (scene.intersect(ray, hit) && !hit.onPatch()) continue;  // sees the light: zero in both
        const Color ca = a.Li(ray, sa), cb = b.Li(ray, sb);
        const double d = (double(ca.x) + ca.y + ca.z - cb.x - cb.y - cb.z) / 3.0;
        sum += d, sum2 += d * d, sumRef += (double(cb.x) + cb.y + cb.z) / 3.0;
      }
      const double m = sum / spp;
      mean[pixel] = m;
      ref[pixel] = sumRef / spp;
      var[pixel] = std::max(0.0, (sum2 - spp * m * m) / (spp - 1));
    }
  });
  if (std::getenv("FSBIAS_MAP")) {  // 8×8 blocks of the difference, % of the image mean
    double all = 0;
    for (double x : ref) all += x;
    all /= double(ref.size());
    for (int by = 0; by < h; by += 8) {
      for (int bx = 0; bx < w; bx += 8) {
        double d = 0;
        for (int y = by; y < std::min(h, by + 8); ++y)
          for (int x = bx; x < std::min(w, bx + 8); ++x) d += mean[size_t(y) * w + x];
        std::printf("%+6.2f ", 100 * d / 64 / all);
      }
      std::printf("\n");
    }
  }
  BiasMeasure r;
  double v = 0;
  for (size_t i = 0; i < mean.size(); ++i) r.diff += mean[i], r.reference += ref[i], v += var[i] / spp;
  const double n = double(mean.size());
  r.diff /= n, r.reference /= n, r.se = std::sqrt(v) / n;
  return r;
}

/// The paired first-shot − NEE image mean of @p desc with the table @p table against NEE at the
/// scene's patch size: path tracer, max depth 3, every light sampled, seed 11.
inline BiasMeasure firstShotImageBias(const SceneDesc& desc, FirstShotTable table, int spp) {
  const RenderScene nee(desc, desc.settings.patchSize), fs(desc, std::move(table));
  IntegratorOptions io;
  io.maxDepth = 3;
  io.lightSampler = LightStrategy::All;  // pairing: both integrators draw the same random numbers
  auto a = makeIntegrator("path", io), b = makeIntegrator("path", io);
  a->preprocess(fs);
  b->preprocess(nee);
  return measurePairedBias(*a, *b, nee, Camera(desc.camera), spp, 11);
}

/// Irradiance that light sample @p s delivers at point @p x with unit normal @p n (front side
/// only, no occlusion), W/m²: the exact point-to-sample term the table's factors integrate
/// (point Φ cosθ/(4πd²), spot Φ cosθ·profile/(∫profile·d²) with @p light the spot's description,
/// area vertex Le (S_i/3) cosθ cosθL/d², directional E⊥ cosθ).
inline Color unoccludedSampleIrradiance(const LightSample& s, const Vec3& x, const Vec3& n, const LightDesc* light = nullptr) {
  if (s.kind == LightSampleKind::Directional) return s.emission * std::max(0.0f, -glm::dot(s.normal, n));
  const Vec3 d = s.position - x;
  const float d2 = glm::dot(d, d);
  const Vec3 wi = d / std::sqrt(d2);
  const float cosX = glm::dot(wi, n);
  if (!(cosX > 0.0f)) return Color(0.0f);
  if (s.kind == LightSampleKind::Point) return s.emission * (cosX / (4.0f * float(kPi) * d2));
  if (s.kind == LightSampleKind::Spot && light) {
    const EmissionProfile profile(*light);
    return s.emission * float(cosX * profile(-wi) / (profile.integral() * d2));
  }
  if (s.kind == LightSampleKind::AreaVertex) {
    const float cosL = -glm::dot(wi, s.normal);
    return cosL > 0.0f ? s.emission * (s.weight * cosX * cosL / d2) : Color(0.0f);
  }
  return Color(0.0f);
}

/// Uniform point on patch @p p (fan triangles chosen by area).
inline Vec3 samplePatch(const Patch& p, Vec2 u) {
  const Vec3 a = p.v[0];
  int tri = 1;
  if (p.count == 4) {
    const float a1 = glm::length(glm::cross(p.v[1] - a, p.v[2] - a)), a2 = glm::length(glm::cross(p.v[2] - a, p.v[3] - a));
    const float t = u.x * (a1 + a2);
    if (t >= a1) tri = 2, u.x = std::min((t - a1) / a2, 0.99999994f);
    else u.x = t / a1;
  }
  const float su = std::sqrt(u.x);
  return a * (1 - su) + p.v[tri] * (su * (1 - u.y)) + p.v[tri + 1] * (su * u.y);
}

/// Brute-force patch-averaged front-side irradiance of patch @p j (channel mean), W/m²: @p n
/// uniform points, each with a shadow ray to every light sample on the front side.
/// True if most of 16 rays leaving @p x over the hemisphere of @p n hit the back of a surface: the
/// point lies inside a closed object (the floor under a box), where the renderer never shades.
inline bool buriedPoint(const RenderScene& scene, const Vec3& x, const Vec3& n) {
  const Frame f(n);
  const Vec3 o = x + n * (1e-5f * std::max(1.0f, maxComponent(glm::abs(x))));
  int back = 0;
  for (int k = 0; k < 16; ++k) {
    const float u = (float(k % 4) + 0.5f) / 4.0f, v = (float(k / 4) + 0.5f) / 4.0f;
    const float r = std::sqrt(u), phi = 2.0f * float(kPi) * v;
    const Vec3 d = f.toWorld(Vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u))));
    Hit h;
    if (scene.intersect(Ray(o, d), h) && glm::dot(h.ng, d) > 0.0f) ++back;
  }
  return back > 8;
}

/// Monte Carlo patch-average irradiance of patch @p j (n uniform points); with @p paired, of the
/// first-shot term minus the exact value. @p exposedOnly: points inside closed objects are skipped
/// (the estimate is then over the exposed part, what an image shows).
inline void patchIrradianceMC(const RenderScene& scene, uint32_t j, int n, uint64_t seed, double& mean, double& se,
                              const FirstShotLighting* paired = nullptr, bool exposedOnly = false) {
  const FirstShotTable& t = *scene.firstShot();
  const Patch& p = t.mesh.patches[j];
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    Sampler s(seed, j, uint64_t(k));
    const Vec3 x = samplePatch(p, s.next2D());
    if (exposedOnly && buriedPoint(scene, x, p.normal)) continue;
    // The shadow ray aims from a point just off the patch straight at the sample (no parallel
    // shift, which would let it cross an area light's plane before its end) and stops just short.
    const Vec3 o = x + p.normal * (1e-6f * std::max(1.0f, maxComponent(glm::abs(x))));
    double e = 0;
    for (const LightSample& ls : t.samples) {
      const Color c = unoccludedSampleIrradiance(ls, x, p.normal, &scene.desc().lights[ls.light]);
      if (maxComponent(c) <= 0.0f) continue;
      const bool dir = ls.kind == LightSampleKind::Directional;
      const Vec3 d = dir ? -ls.normal : ls.position - o;
      const float dist = dir ? INFINITY : glm::length(d);
      if (scene.occluded(Ray(o, d / glm::length(d), 0.0f, dir ? dist : dist * (1.0f - 1e-5f)))) continue;
      e += (double(c.x) + c.y + c.z) / 3.0;
    }
    if (paired) {  // the first-shot term's per-point irradiance minus the exact one
      Hit h;
      h.p = x, h.ng = p.normal, h.patch = j;
      const Color f = paired->irradiance(h, true);
      e = (double(f.x) + f.y + f.z) / 3.0 - e;
    }
    sum += e, sum2 += e * e;
  }
  // Skipped (buried) points count as 0: the mean stays an average over the whole patch area.
  mean = sum / n;
  se = std::sqrt(std::max(0.0, (sum2 / n - mean * mean) / (n - 1)));
}

}  // namespace firstshot::test
