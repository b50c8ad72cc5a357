// The path tracer's ray throughput against raw Embree on the same scene (the Cornell box), in one
// run: BM_PathTracer counts every closest-hit and shadow ray of whole 1-spp passes (shading,
// sampling and film included), with NEE to every light (tree:0) and by the light tree (tree:1, the
// renderer's default); BM_RawEmbreeIncoherent times plain rtcIntersect1 calls on random
// rays (origins uniform in the box, directions uniform on the sphere). Both on 1 and 2 threads.
// BM_PathTracerOverRaw: the two in alternation, 1-spp pass against 2^17 raw rays, and their ratio.
// BM_HemisphereRays: an irradiance record's hemisphere rays as single rays, packets and streams.
// BM_CameraRays: Cornell's camera rays (128², 4 × 4 pixel blocks) as single rays and packets.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/scene/scene_desc.h"
#include "render/integrators/integrator.h"
#include "render/loop/renderer.h"
#include "render/output/film.h"
#include "render/scene/camera.h"
#include "render/scene/embree_scene.h"
#include "render/scene/render_scene.h"

namespace {

using namespace firstshot;

struct Fixture {
  SceneDesc desc;
  std::unique_ptr<RenderScene> scene;
  std::unique_ptr<Integrator> tree, all;  ///< NEE by the light tree (the default) and to every light
  std::vector<Ray> randomRays;
  std::vector<Ray> hemisphereRays;  ///< an irradiance record's 2M² = 512 cosine-stratified rays, at 64 camera hits
  std::vector<Ray> hemisphereBlocks;  ///< the same rays, each record's in 4 × 4 blocks of neighbouring strata
  std::vector<Ray> cameraRays;  ///< one jittered camera ray per pixel, in 4 × 4 blocks of pixels

  Fixture() {
    desc = loadScene(std::string(FIRSTSHOT_SOURCE_DIR) + "/scenes/cornell.json");
    desc.camera.width = desc.camera.height = 128;
    scene = std::make_unique<RenderScene>(desc);
    tree = makeIntegrator("path", IntegratorOptions{});
    tree->preprocess(*scene);
    IntegratorOptions allOptions;
    allOptions.lightSampler = LightStrategy::All;
    all = makeIntegrator("path", allOptions);
    all->preprocess(*scene);
    Vec3d lo, hi;
    desc.bounds(lo, hi);
    Sampler s(1, 0, 0);
    randomRays.resize(size_t(1) << 20);
    for (Ray& r : randomRays) {
      const Vec3 u(s.next1D(), s.next1D(), s.next1D());
      r = Ray(Vec3(lo) + u * Vec3(hi - lo), squareToUniformSphere(s.next2D()));
    }
    const Camera camera(desc.camera);
    for (int by = 0; by < camera.height(); by += 4)
      for (int bx = 0; bx < camera.width(); bx += 4)
        for (int y = by; y < by + 4; ++y)
          for (int x = bx; x < bx + 4; ++x) {
            const Vec2 j = s.next2D();
            cameraRays.push_back(camera.generateRay(float(x) + j.x, float(y) + j.y));
          }
    const int M = 16, N = 2 * M;  // the cache's default of 512 samples
    for (int point = 0; point < 64; ++point) {
      Hit hit;
      const Vec2 px = s.next2D();
      if (!scene->intersect(camera.generateRay(px.x * float(camera.width()), px.y * float(camera.height())), hit)) continue;
      const Frame frame(hit.ng);
      const size_t first = hemisphereRays.size();
      for (int j = 0; j < M; ++j)
        for (int k = 0; k < N; ++k) {
          const Vec3 w = frame.toWorld(squareToCosineHemisphereStratum(j, k, M, N, s.next2D()));
          hemisphereRays.emplace_back(hit.spawnOrigin(w), w);
        }
      for (int jb = 0; jb < M; jb += 4)
        for (int kb = 0; kb < N; kb += 4)
          for (int j = jb; j < jb + 4; ++j)
            for (int k = kb; k < kb + 4; ++k) hemisphereBlocks.push_back(hemisphereRays[first + size_t(j * N + k)]);
    }
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

/// 1-spp passes of the Cornell fixture's path tracer on @p threads, accumulated into one film as a
/// progressive render does; next() renders the next pass.
struct ProgressivePasses {
  const Camera camera;
  RenderOptions options;
  Film film;
  int pass = 0;
  ProgressivePasses(const Fixture& f, int threads) : camera(f.desc.camera), film(camera.width(), camera.height()) {
    options.spp = 1;
    options.threads = threads;
  }
  RenderStats next(const Integrator& integrator) {
    options.firstSample = pass++;
    return render(integrator, camera, film, options);
  }
};

void BM_PathTracer(benchmark::State& state) {
  Fixture& f = fixture();
  ProgressivePasses passes(f, int(state.range(0)));
  uint64_t rays = 0, samples = 0;
  for (auto _ : state) {
    const RenderStats st = passes.next(state.range(1) ? *f.tree : *f.all);
    rays += st.rays;
    samples += st.cameraSamples;
  }
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["samples/s"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate);
  state.counters["rays/sample"] = double(rays) / double(samples);
}

/// rtcIntersect1 on randomRays[first, first + count) in @p arena's threads; @return the hits.
size_t traceRandomRays(const Fixture& f, tbb::task_arena& arena, size_t first, size_t count) {
  const EmbreeScene& embree = f.scene->embree();
  std::atomic<size_t> hits{0};
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(first, first + count, 4096), [&](const tbb::blocked_range<size_t>& r) {
      enableFlushToZero();
      hits += embree.intersectRaw(f.randomRays.data() + r.begin(), r.size());
    });
  });
  return hits.load();
}

void BM_RawEmbreeIncoherent(benchmark::State& state) {
  Fixture& f = fixture();
  tbb::task_arena arena(int(state.range(0)));
  uint64_t rays = 0;
  size_t hits = 0;
  for (auto _ : state) {
    hits += traceRandomRays(f, arena, 0, f.randomRays.size());
    rays += f.randomRays.size();
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["hit fraction"] = double(hits) / double(rays);
}

/// The ratio of the two above taken in alternation: each iteration times one 1-spp pass of the
/// path tracer (light tree) and then 2^17 raw random rays (about as long), so that a machine whose
/// speed drifts between benchmarks (shared hosts) slows both alike. "ratio" = path tracer rays/s
/// over raw rays/s, summed over all iterations.
void BM_PathTracerOverRaw(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  Fixture& f = fixture();
  ProgressivePasses passes(f, int(state.range(0)));
  tbb::task_arena arena(int(state.range(0)));
  const size_t slice = size_t(1) << 17;
  uint64_t pathRays = 0, rawRays = 0;
  size_t hits = 0;
  double pathSeconds = 0.0, rawSeconds = 0.0;
  for (auto _ : state) {
    const Clock::time_point t0 = Clock::now();
    pathRays += passes.next(*f.tree).rays;
    const Clock::time_point t1 = Clock::now();
    hits += traceRandomRays(f, arena, rawRays % f.randomRays.size(), slice);
    rawRays += slice;
    pathSeconds += std::chrono::duration<double>(t1 - t0).count();
    rawSeconds += std::chrono::duration<double>(Clock::now() - t1).count();
  }
  benchmark::DoNotOptimize(hits);
  const double pathRate = double(pathRays) / pathSeconds, rawRate = double(rawRays) / rawSeconds;
  state.counters["path Mrays/s"] = pathRate * 1e-6;
  state.counters["raw Mrays/s"] = rawRate * 1e-6;
  state.counters["ratio"] = pathRate / rawRate;
}

/// The irradiance cache's hemisphere rays (one record's 512 rays after another), one thread, by
/// Embree layout: 0 single rtcIntersect1 calls, 1 packets of 16 (16 strata of one ring), 2 one stream
/// (rtcIntersect1M) per record, 3 packets of 16 over 4 × 4 blocks of neighbouring strata.
void BM_HemisphereRays(benchmark::State& state) {
  Fixture& f = fixture();
  const EmbreeScene& embree = f.scene->embree();
  const std::vector<Ray>& rays = state.range(0) == 3 ? f.hemisphereBlocks : f.hemisphereRays;
  size_t hits = 0;
  uint64_t traced = 0;
  enableFlushToZero();
  for (auto _ : state) {
    for (size_t first = 0; first < rays.size(); first += 512) {
      const size_t n = std::min<size_t>(512, rays.size() - first);
      switch (state.range(0)) {
        case 0: hits += embree.intersectRaw(rays.data() + first, n); break;
        case 1:
        case 3: hits += embree.intersectRawPackets(rays.data() + first, n); break;
        default: hits += embree.intersectRawStream(rays.data() + first, n); break;
      }
    }
    traced += rays.size();
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays/s"] = benchmark::Counter(double(traced), benchmark::Counter::kIsRate);
  state.counters["hit fraction"] = double(hits) / double(traced);
}

}  // namespace

BENCHMARK(BM_HemisphereRays)->ArgNames({"layout"})->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
/// One camera ray per pixel (128², one thread), by layout: 0 single rtcIntersect1 calls, 1 one packet
/// of 16 per 4 × 4 block (rtcIntersect16), 2 the renderer's two packets of 8 per block (intersect16).
void BM_CameraRays(benchmark::State& state) {
  Fixture& f = fixture();
  const EmbreeScene& embree = f.scene->embree();
  const std::vector<Ray>& rays = f.cameraRays;
  size_t hits = 0;
  uint64_t traced = 0;
  enableFlushToZero();
  bool active[16], found[16];
  std::fill(active, active + 16, true);
  Hit blockHits[16];
  for (auto _ : state) {
    switch (state.range(0)) {
      case 0: hits += embree.intersectRaw(rays.data(), rays.size()); break;
      case 1: hits += embree.intersectRawPackets(rays.data(), rays.size()); break;
      default:
        for (size_t first = 0; first + 16 <= rays.size(); first += 16) {
          embree.intersect16(rays.data() + first, active, 16, blockHits, found);
          hits += size_t(std::count(found, found + 16, true));
        }
    }
    traced += rays.size();
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays/s"] = benchmark::Counter(double(traced), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CameraRays)->ArgNames({"layout"})->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(BM_PathTracer)->ArgNames({"threads", "tree"})->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_RawEmbreeIncoherent)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_PathTracerOverRaw)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(4.0);

BENCHMARK_MAIN();
