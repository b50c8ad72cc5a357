// The path tracer's ray throughput against raw Embree on the same scene (the Cornell box), in one
// run: BM_PathTracer counts every closest-hit and shadow ray of whole 1-spp passes (shading,
// sampling and film included), with NEE to every light (tree:0) and by the light tree (tree:1, the
// renderer's default); BM_RawEmbreeIncoherent times plain rtcIntersect1 calls on random
// rays (origins uniform in the box, directions uniform on the sphere). Both on 1 and 2 threads.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <memory>

#include "common/rng.h"
#include "common/sampling.h"
#include "common/scene_desc.h"
#include "render/camera.h"
#include "render/embree_scene.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/render_scene.h"
#include "render/renderer.h"

namespace {

using namespace fs;

struct Fixture {
  SceneDesc desc;
  std::unique_ptr<RenderScene> scene;
  std::unique_ptr<Integrator> tree, all;  ///< NEE by the light tree (the default) and to every light
  std::vector<Ray> randomRays;

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
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_PathTracer(benchmark::State& state) {
  Fixture& f = fixture();
  const Camera camera(f.desc.camera);
  RenderOptions ro;
  ro.spp = 1;
  ro.threads = int(state.range(0));
  uint64_t rays = 0, samples = 0, pass = 0;
  Film film(camera.width(), camera.height());  // accumulated over the passes, as a progressive render does
  for (auto _ : state) {
    ro.firstSample = int(pass++);
    const RenderStats st = render(state.range(1) ? *f.tree : *f.all, camera, film, ro);
    rays += st.rays;
    samples += st.cameraSamples;
  }
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["samples/s"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate);
  state.counters["rays/sample"] = double(rays) / double(samples);
}

void BM_RawEmbreeIncoherent(benchmark::State& state) {
  Fixture& f = fixture();
  const EmbreeScene& embree = f.scene->embree();
  tbb::task_arena arena(int(state.range(0)));
  uint64_t rays = 0;
  std::atomic<size_t> hits{0};
  for (auto _ : state) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, f.randomRays.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        enableFlushToZero();
        hits += embree.intersectRaw(f.randomRays.data() + r.begin(), r.size());
      });
    });
    rays += f.randomRays.size();
  }
  benchmark::DoNotOptimize(hits.load());
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["hit fraction"] = double(hits.load()) / double(rays);
}

}  // namespace

BENCHMARK(BM_PathTracer)->ArgNames({"threads", "tree"})->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_RawEmbreeIncoherent)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

BENCHMARK_MAIN();
