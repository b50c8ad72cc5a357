// Item buffers: milliseconds per light sample (all views of a window, rendered and read back) for the
// GL (OSMesa, EGL) and Embree back ends on the shipped Cornell box split into ~24k patches.
//   bench_item_buffer [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "common/formats/load_scene.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/gl/gl_item_buffer.h"
#include "preprocess/window.h"

namespace firstshot {
namespace {

/// The shipped Cornell box (scenes/cornell.json) split into patches of at most @p size.
PatchMesh cornellPatches(double size) {
  return buildPatches(loadScene(std::string(FIRSTSHOT_SOURCE_DIR) + "/scenes/cornell.json"), size);
}

struct Fixture {
  PatchMesh mesh = cornellPatches(0.009);
  ItemGeometry geometry = ItemGeometry::fromPatches(mesh);
  std::map<std::string, std::unique_ptr<ItemBufferRenderer>> renderers;

  ItemBufferRenderer* get(const std::string& name) {
    auto it = renderers.find(name);
    if (it != renderers.end()) return it->second.get();
    std::unique_ptr<ItemBufferRenderer> r;
    try {
      if (name == "embree") r = std::make_unique<EmbreeItemBuffer>(geometry, geometry.bounds);
      else r = std::make_unique<GLItemBuffer>(geometry, geometry.bounds, parseGLBackend(name));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s unavailable: %s\n", name.c_str(), e.what());
    }
    return (renderers[name] = std::move(r)).get();
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void benchWindow(benchmark::State& state, const std::string& backend, WindowKind kind,
                 EmbreeRayMode mode = EmbreeRayMode::Packet16) {
  Fixture& f = fixture();
  ItemBufferRenderer* r = f.get(backend);
  if (!r) {
    state.SkipWithError("back end unavailable");
    return;
  }
  if (auto* e = dynamic_cast<EmbreeItemBuffer*>(r)) e->setRayMode(mode);
  const int R = static_cast<int>(state.range(0));
  const Window w = kind == WindowKind::Cube ? makeCubeWindow(R) : makeHemicubeWindow(R);
  std::vector<View> views;
  if (kind == WindowKind::Cube)
    views = placeWindow(w, {0.278, 0.274, 0.28}, Framed(Vec3d(0, 1, 0)));
  else
    views = placeWindow(w, {0.278, 0.5483, 0.2795}, Framed(Vec3d(0, -1, 0)), areaLightEyeOffset(f.geometry.bounds));
  std::vector<uint32_t> ids;
  size_t seen = 0;
  for (auto _ : state) {
    for (const View& v : views) {
      r->render(v, ids);
      seen += ids[ids.size() / 2] != kNoPatch;
    }
    benchmark::ClobberMemory();
  }
  benchmark::DoNotOptimize(seen);
  state.counters["patches"] = f.mesh.size();
  state.counters["Mpix/s"] =
      benchmark::Counter(double(w.pixelCount()) * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}

void registerAll() {
  for (const char* backend : {"osmesa", "egl", "embree"})
    for (auto [kind, kname] : {std::pair{WindowKind::Cube, "cube"}, std::pair{WindowKind::Hemicube, "hemicube"}})
      benchmark::RegisterBenchmark((std::string(kname) + "/" + backend).c_str(),
                                   [backend = std::string(backend), kind = kind](benchmark::State& s) {
                                     benchWindow(s, backend, kind);
                                   })
          ->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime();
  // Embree ray layouts (identical results): which one is fastest here.
  const std::pair<EmbreeRayMode, const char*> modes[] = {{EmbreeRayMode::Single, "single"},
                                                        {EmbreeRayMode::Packet8, "packet8"},
                                                        {EmbreeRayMode::Packet16, "packet16"},
                                                        {EmbreeRayMode::Stream, "stream1M"}};
  for (auto [mode, mname] : modes)
    benchmark::RegisterBenchmark((std::string("cube/embree-") + mname).c_str(),
                                 [mode = mode](benchmark::State& s) { benchWindow(s, "embree", WindowKind::Cube, mode); })
        ->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace
}  // namespace firstshot

int main(int argc, char** argv) {
  firstshot::registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::printf("mesh: %u patches\n", firstshot::fixture().mesh.size());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
