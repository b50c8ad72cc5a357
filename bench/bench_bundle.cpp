// Ray-bundle stochastic iteration: the cost of one iteration (global transfer: outgoing radiance of
// every element, B² lines with successive hits, ordered gathering) against the patch count and the
// bundle resolution B, and the memory it needs. The scene: a closed 2 m room with a box and a
// glossy block inside, its patch size chosen for ~700 to ~1.3 M patches (--benchmark_filter picks
// one; run each case in its own process to read its peak RSS):
//   build/dev/bench/bench_bundle --benchmark_filter='BM_BundleIteration/scene:1/B:1024/'   (1.34 M patches)
// Counters: patches, lines per iteration, hits per line, state (the per-element arrays, MB),
// peak RSS and the RSS the integrator added on top of the scene (MB).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>
#include <tbb/task_arena.h>

#include <fmt/core.h>

#include <cstdio>
#include <map>
#include <memory>

#include "common/formats/json/scene_json.h"
#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "render/integrators/bundle/integrator.h"
#include "render/scene/render_scene.h"

namespace {

using namespace firstshot;

SceneDesc room() {
  return parseSceneJson(R"({
    "camera": {"position": [0, 1, -0.9], "look_at": [0, 0.5, 0], "fov_y": 60, "resolution": [64, 64]},
    "materials": {"wall": {"type": "diffuse", "albedo": 0.6},
                  "gloss": {"type": "glossy", "albedo": 0.2, "specular": 0.5, "exponent": 10},
                  "lamp": {"type": "diffuse", "albedo": 0, "emission": 5}},
    "shapes": [{"type": "box", "material": "wall", "min": [-1, 0, -1], "max": [1, 2, 1], "flip_normals": true},
               {"type": "box", "material": "wall", "min": [-0.6, 0, -0.2], "max": [-0.1, 0.8, 0.3]},
               {"type": "box", "material": "gloss", "min": [0.2, 0, 0.1], "max": [0.6, 0.4, 0.5]},
               {"type": "quad", "material": "lamp", "vertices": [[-0.2, 1.99, -0.2], [0.2, 1.99, -0.2], [0.2, 1.99, 0.2], [-0.2, 1.99, 0.2]]}]})",
                        "bench-room.json");
}

/// Patch sizes by index: the room with ≈ 700, 1.3 M, 11 k, 173 k patches; 4: sierpinski-glossy.
constexpr double kPatchSizes[] = {0.2, 0.0045, 0.05, 0.0125, 0.05};

/// Resident set size now, MB (/proc/self/statm).
double rssMb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / 1e6;
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;  // KiB on Linux
}

void BM_BundleIteration(benchmark::State& state) {
  const double patchSize = kPatchSizes[state.range(0)];
  const int B = int(state.range(1));
  static std::map<double, std::unique_ptr<RenderScene>> scenes;  // built once per patch size
  auto& scene = scenes[patchSize];
  if (!scene)  // scene 4: sierpinski-glossy, whose lines cross many surfaces
    scene = std::make_unique<RenderScene>(
        state.range(0) == 4 ? loadScene(std::string(FIRSTSHOT_SOURCE_DIR) + "/scenes/sierpinski-glossy.json") : room(), patchSize);
  const double sceneRss = rssMb();
  BundleIntegrator bundle(IntegratorOptions{});
  BundleSettings settings;
  settings.resolution = B;
  settings.allHits = state.range(3) != 0;
  bundle.setSettings(settings);
  bundle.preprocess(*scene);
  tbb::task_arena arena(int(state.range(2)));
  int k = 0;
  uint64_t rays = 0;
  for (auto _ : state) {
    arena.execute([&] { bundle.beginPass(k, 1); });
    rays += bundle.transfer().lastRays();
    ++k;
  }
  const auto& t = bundle.transfer();
  const double elements = t.elements().size();
  const double lines = 3.14159265 / 4 * double(B) * double(B);  // inside the bounding disk
  state.counters["patches"] = double(scene->mesh().size());
  state.counters["lines"] = lines;
  state.counters["hits/line"] = double(rays) / double(k) / lines - 1.0;  // the last ray of a line misses
  state.counters["state_MB"] = elements * (2 * 5 * sizeof(Color) + sizeof(BundleElement)) / 1e6;
  state.counters["peak_RSS_MB"] = peakRssMb();
  state.counters["bundle_RSS_MB"] = rssMb() - sceneRss;  // what the integrator and its iterations added
}

}  // namespace

BENCHMARK(BM_BundleIteration)
    ->ArgNames({"scene", "B", "threads", "allhits"})
    ->Args({0, 64, 2, 0})->Args({0, 256, 2, 0})->Args({0, 1024, 2, 0})
    ->Args({2, 256, 2, 0})->Args({3, 256, 2, 0})
    ->Args({1, 64, 2, 0})->Args({1, 256, 2, 0})->Args({1, 1024, 2, 0})
    ->Args({0, 256, 1, 0})
    // successive closest hits (allhits:0) against one all-hits query per line (allhits:1)
    ->Args({0, 1024, 1, 0})->Args({0, 1024, 1, 1})->Args({3, 1024, 1, 0})->Args({3, 1024, 1, 1})
    ->Args({4, 512, 1, 0})->Args({4, 512, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5);

BENCHMARK_MAIN();
