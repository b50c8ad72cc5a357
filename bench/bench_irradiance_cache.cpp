// The irradiance cache integrator: time and error against a path-traced reference at
// a = 0.05, 0.1, 0.2, 0.3 on the Cornell box and the many-lights room, both with first-shot
// tables; records per second; and the cache's own lookup and insert rates on 1 and 2 threads.
// A plain program that prints Markdown tables (those of docs/measurements.md, "Irradiance cache").
//
// Error: both integrators are evaluated on the renderer's own camera rays (seed, pixel, sample);
// per ray the reference is the mean of P path-traced estimates with the same path length (B + 1
// bounces) and the same first-shot table, and the cache's value the mean of 16 estimates (the
// renderer's and 15 with other light samples; the records used are the same). The per-pixel
// difference d has no aliasing noise, and
// mean(d)² − var(d)/n estimates the squared bias of each pixel and channel without the
// reference's noise. Reported: rel. RMSE = √(mean bias²)/mean(r) (RMSE over the mean, "NRMSE" in
// bench/image_metrics.h), per-pixel rel. RMSE = √(mean of bias²/(r + ε)²) with ε = 0.01·mean(r)
// (image_metrics.h's "rel. RMSE", dominated by the darkest pixels), and the relative difference
// of the image means.
//
// Usage: bench_irradiance_cache [--quick]   (--quick: smaller images and reference)
#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/scene/camera.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/integrators/path/integrator.h"
#include "render/loop/renderer.h"

using namespace firstshot;

namespace {

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Reference {
  int width = 0, height = 0, spp = 0;
  uint64_t seed = 0;
  std::vector<Vec3d> L;  ///< per pixel and sample
  std::vector<Vec3d> pixel;  ///< per pixel: mean over its samples
  double mean = 0;
};

Ray cameraRay(const Camera& camera, uint64_t seed, size_t p, int k, Sampler& s) {
  s = Sampler(seed, p, uint64_t(k));
  const Vec2 j = s.next2D();
  return camera.generateRay(float(p % size_t(camera.width())) + j.x, float(p / size_t(camera.width())) + j.y);
}

// Not tests/irradiance_cache_util.h's pairedReference: a bench does not use the tests, and its camera rays and per-pixel means differ.
Reference reference(const Integrator& path, const Camera& camera, int spp, int perRay, uint64_t seed) {
  Reference r;
  r.width = camera.width(), r.height = camera.height(), r.spp = spp, r.seed = seed;
  const size_t pixels = size_t(r.width) * size_t(r.height);
  r.L.assign(pixels * size_t(spp), Vec3d(0.0));
  r.pixel.assign(pixels, Vec3d(0.0));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels), [&](const tbb::blocked_range<size_t>& range) {
    enableFlushToZero();
    for (size_t p = range.begin(); p < range.end(); ++p)
      for (int k = 0; k < spp; ++k) {
        Sampler cam(0, 0, 0);
        const Ray ray = cameraRay(camera, seed, p, k, cam);
        Vec3d sum(0.0);
        for (int q = 0; q < perRay; ++q) {
          Sampler s(seed ^ 0x5eed, p, uint64_t(k) * uint64_t(perRay) + uint64_t(q));
          s.next2D();
          sum += Vec3d(path.Li(ray, s));
        }
        r.L[p * size_t(spp) + size_t(k)] = sum / double(perRay);
        r.pixel[p] += sum / double(perRay) / double(spp);
      }
  });
  double m = 0;
  for (const Vec3d& v : r.pixel) m += (v.x + v.y + v.z) / 3.0;
  r.mean = m / double(pixels);
  return r;
}

struct Errors {
  double rel = 0, nrmse = 0, meanBias = 0;  ///< meanBias: (mean of the image − mean of the reference) / mean of the reference
};

Errors pairedErrors(const Integrator& ic, const Camera& camera, const Reference& ref, int perRay) {
  const size_t pixels = size_t(ref.width) * size_t(ref.height);
  const double eps = 0.01 * ref.mean;
  std::vector<double> rel(pixels), abs2(pixels), diff(pixels);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels), [&](const tbb::blocked_range<size_t>& range) {
    enableFlushToZero();
    for (size_t p = range.begin(); p < range.end(); ++p) {
      Vec3d sum(0.0), sum2(0.0);
      for (int k = 0; k < ref.spp; ++k) {
        Sampler s(0, 0, 0);
        const Ray ray = cameraRay(camera, ref.seed, p, k, s);
        // The renderer's estimate along the ray and perRay − 1 more with other random numbers
        // (the same records, other light samples), averaged: the noise of direct light drops out.
        Vec3d L(ic.Li(ray, s));
        for (int q = 1; q < perRay; ++q) {
          Sampler t(ref.seed ^ 0x1c, p, uint64_t(k) * uint64_t(perRay) + uint64_t(q));
          t.next2D();
          L += Vec3d(ic.Li(ray, t));
        }
        const Vec3d d = L / double(perRay) - ref.L[p * size_t(ref.spp) + size_t(k)];
        sum += d, sum2 += d * d;
      }
      const double n = ref.spp;
      const Vec3d m = sum / n, var = (sum2 - n * m * m) / (n - 1), b2 = m * m - var / n;
      rel[p] = abs2[p] = 0;
      diff[p] = (m.x + m.y + m.z) / 3.0;
      for (int c = 0; c < 3; ++c) {
        rel[p] += b2[c] / ((ref.pixel[p][c] + eps) * (ref.pixel[p][c] + eps));
        abs2[p] += b2[c];
      }
    }
  });
  double r = 0, a = 0, d = 0;
  for (size_t p = 0; p < pixels; ++p) r += rel[p], a += abs2[p], d += diff[p];
  const double n = 3.0 * double(pixels);
  return {std::sqrt(std::max(0.0, r / n)), std::sqrt(std::max(0.0, a / n)) / ref.mean, d / double(pixels) / ref.mean};
}

struct Case {
  std::string name, file;
  int width, height;
  PrimaryMode primary;
};

/// A named change to the default settings.
struct Variant {
  std::string name;
  bool gradients, neighbourClamp;
};

void runScene(const Case& c, bool quick, const std::vector<float>& accuracies, const std::vector<Variant>& variants) {
  SceneDesc desc = loadScene(std::string(FIRSTSHOT_SOURCE_DIR) + "/scenes/" + c.file);
  desc.camera.width = quick ? c.width / 2 : c.width;
  desc.camera.height = quick ? c.height / 2 : c.height;
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.quiet = true;
  auto t0 = std::chrono::steady_clock::now();
  const RenderScene scene(desc, preprocessScene(desc, po));
  const double tTable = seconds(t0);
  const Camera camera(desc.camera);
  const int bounces = 3, spp = 4, perRay = quick ? 16 : 64;
  const uint64_t seed = 7;
  IntegratorOptions io;
  io.maxDepth = bounces + 1;
  io.primary = c.primary;
  PathIntegrator path(io);
  path.preprocess(scene);
  t0 = std::chrono::steady_clock::now();
  const Reference ref = reference(path, camera, spp, perRay, seed);
  const double tRef = seconds(t0);
  fmt::print("\n### {} ({}×{}, {} patches, first-shot table in {:.2f} s, --primary {})\n", c.name, desc.camera.width,
             desc.camera.height, scene.mesh().size(), tTable, c.primary == PrimaryMode::Exact ? "exact" : "patch");
  fmt::print("Reference: paths of {} bounces, {} per camera ray × {} rays per pixel ({:.1f} s).\n\n", bounces + 1, perRay,
             spp, tRef);
  for (const Variant& v : variants) {
    fmt::print("\n{}:\n\n", v.name);
    fmt::print("| a | records (by level) | fill + render | CPU | records/s | rel. RMSE | per-pixel rel. RMSE | mean |\n"
               "|---|---|---|---|---|---|---|---|\n");
    for (float a : accuracies) {
      IrradianceCacheSettings s;
      s.accuracy = a;
      s.gradients = v.gradients;
      s.neighbourClamp = v.neighbourClamp;
      s.bounces = bounces;
      s.twoPass = true;
      s.seed = seed;
      IrradianceCacheIntegrator ic(io, s);
      t0 = std::chrono::steady_clock::now();
      const std::clock_t cpu0 = std::clock();
      ic.preprocess(scene);
      Film film(camera.width(), camera.height());
      RenderOptions ro;
      ro.spp = spp;
      ro.seed = seed;
      const RenderStats st = render(ic, camera, film, ro);
      const double t = seconds(t0), cpu = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
      const IrradianceCacheStats cs = ic.stats();
      const Errors e = pairedErrors(ic, camera, ref, 16);
      std::string levels;
      for (size_t l = 0; l < cs.perLevel.size(); ++l) levels += fmt::format("{}{}", l ? "+" : "", cs.perLevel[l]);
      fmt::print("| {:.2f} | {} ({}) | {:.2f} + {:.2f} s | {:.1f} s | {:.0f} | {:.4f} | {:.4f} | {:+.2f}% |\n", a, cs.records,
                 levels, cs.fillSeconds, st.seconds, cpu, double(cs.records) / t, e.nrmse, e.rel, 100.0 * e.meanBias);
    }
  }
}

/// Lookups and inserts per second on a cache of the Cornell box's level-0 records.
void cacheRates() {
  SceneDesc desc = loadScene(std::string(FIRSTSHOT_SOURCE_DIR) + "/scenes/cornell.json");
  desc.camera.width = desc.camera.height = 128;
  const RenderScene scene(desc);
  IrradianceCacheSettings s;
  s.accuracy = 0.1f;
  s.bounces = 1;
  s.samples = 64;
  s.twoPass = true;
  IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  ic.preprocess(scene);
  const std::vector<IrradianceRecord> records = ic.cache().records(0);
  // Query points: camera-visible surface points of random pixels.
  const Camera camera(desc.camera);
  std::vector<std::pair<Vec3, Vec3>> queries;
  Sampler rng(3, 0, 0);
  while (queries.size() < 200000) {
    Hit hit;
    const Ray ray = camera.generateRay(rng.next1D() * 128.0f, rng.next1D() * 128.0f);
    if (scene.intersect(ray, hit) && hit.onPatch())
      queries.emplace_back(hit.p, glm::dot(hit.ng, ray.d) < 0 ? hit.ng : -hit.ng);
  }
  fmt::print("\n### Cache operations (Cornell box, {} level-0 records, a = 0.1)\n\n", records.size());
  fmt::print("| operation | 1 thread | 2 threads |\n|---|---|---|\n");
  double rate[2];
  size_t found = 0;
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::task_arena arena(threads);
    std::atomic<size_t> hits{0};
    const auto t0 = std::chrono::steady_clock::now();
    const int rounds = 10;
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, queries.size() * rounds, 4096), [&](const tbb::blocked_range<size_t>& r) {
        size_t h = 0;
        for (size_t i = r.begin(); i < r.end(); ++i) {
          const auto& q = queries[i % queries.size()];
          IrradianceEstimate est;
          ic.cache().lookup(0, q.first, q.second, true, est);
          h += est.count > 0;
        }
        hits += h;
      });
    });
    rate[threads - 1] = double(queries.size() * rounds) / seconds(t0);
    found = hits / rounds;
  }
  fmt::print("| lookups (eq. 5 + 6, gradients), M/s | {:.2f} | {:.2f} |\n", rate[0] * 1e-6, rate[1] * 1e-6);
  // Inserts with neighbour clamping, one writer, and while another thread looks up.
  Vec3d lo, hi;
  desc.bounds(lo, hi);
  for (int readers = 0; readers <= 1; ++readers) {
    IrradianceCache cache(Vec3(lo), Vec3(hi), {0.1f});
    std::atomic<bool> done{false};
    std::thread reader([&] {
      size_t i = 0;
      while (readers && !done.load()) {
        IrradianceEstimate est;
        const auto& q = queries[i++ % queries.size()];
        cache.lookup(0, q.first, q.second, true, est);
      }
    });
    const auto t0 = std::chrono::steady_clock::now();
    for (int rep = 0; rep < 5; ++rep)
      for (IrradianceRecord r : records) {
        r.p += Vec3(1e-4f * float(rep));
        cache.insert(0, r, true);
      }
    rate[readers] = double(records.size() * 5) / seconds(t0);
    done = true;
    reader.join();
  }
  fmt::print("| inserts with neighbour clamping, k/s (alone / beside a reader) | {:.1f} | {:.1f} |\n", rate[0] * 1e-3,
             rate[1] * 1e-3);
  fmt::print("\n{:.1f}% of the query points found records.\n", 100.0 * double(found) / double(queries.size()));
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const std::vector<float> accuracies = {0.05f, 0.1f, 0.2f, 0.3f};
  fmt::print("## Irradiance cache (B = 3 bounces, N = 512, two passes, 4 spp)\n");
  const Variant all{"Defaults (gradients, footprint clamp 1.5–100 px, neighbour clamp)", true, true};
  const Variant plain{"Without gradients and neighbour clamping (Ward 1988 + footprint clamp)", false, false};
  runScene({"Cornell box", "cornell.json", 128, 128, PrimaryMode::Exact}, quick, accuracies, {all, plain});
  runScene({"Many lights", "many-lights.json", 160, 120, PrimaryMode::Patch}, quick, accuracies, {all, plain});
  cacheRates();
  return 0;
}
