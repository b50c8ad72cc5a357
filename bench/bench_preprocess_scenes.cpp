// The whole preprocessing of shipped scenes at their own settings (adaptive patches, automatic light
// tessellation), 2 threads: wall time per run, and as counters the patches, light samples, factors and
// the size of the written .fsd. The metre-scale Cornell box's goals: ≤ 3 s and ≤ 30 MB.
//   bench_preprocess_scenes [--benchmark_filter=cornell-metre]
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "preprocess/preprocessor.h"

namespace firstshot {
namespace {

void BM_PreprocessScene(benchmark::State& state, const std::string& name) {
  const SceneDesc scene = loadScene(std::string(FIRSTSHOT_SOURCE_DIR) + "/scenes/" + name + ".json");
  PreprocessOptions o = defaultOptions(scene);
  o.threads = 2;
  o.quiet = true;
  const std::string path = (std::filesystem::temp_directory_path() / ("bench-" + name + ".fsd")).string();
  FirstShotTable t;
  for (auto _ : state) {
    t = preprocessScene(scene, o);
    writeFirstShot(path, t);
  }
  state.counters["patches"] = double(t.mesh.size());
  state.counters["samples"] = double(t.samples.size());
  state.counters["factors"] = double(t.nonZeros());
  state.counters["fsd_MB"] = double(std::filesystem::file_size(path)) / 1e6;
  std::filesystem::remove(path);
}

BENCHMARK_CAPTURE(BM_PreprocessScene, cornell-metre, std::string("cornell-metre"))->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_PreprocessScene, cornell, std::string("cornell"))->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_PreprocessScene, many-lights, std::string("many-lights"))->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace firstshot

BENCHMARK_MAIN();
