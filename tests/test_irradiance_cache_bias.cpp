// The irradiance cache at its defaults against path tracing on the shipped scenes. Past its cached
// bounces the cache continues by path tracing, so its image means must agree with path tracing's
// (target: within 0.5%, σ from the samples). Records are shared by all pixels of a run, so runs
// (independent seeds, each with its own cache) are the independent samples; path tracing's pixels
// are independent, so its σ comes from the pixels. With a first-shot table the reference is path
// tracing over the same table: the comparison isolates the cache (first-shot's own bias is
// test_firstshot_bias's subject).
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "tests/bias_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

struct CacheBias {
  double path = 0, pathSe = 0;  ///< image mean of path tracing and its standard error
  double cache = 0, cacheSe = 0;
  double relative() const { return (cache - path) / path; }
  double relativeSe() const { return std::sqrt(cacheSe * cacheSe + pathSe * pathSe) / path; }
};

double greyMean(const Film& film, double& se) {
  double m = 0, v = 0;
  for (int c = 0; c < 3; ++c) {
    double mc, sc;
    test::imageMean(film, c, mc, sc);
    m += mc / 3.0, v += sc * sc / 9.0;
  }
  se = std::sqrt(v);  // channels treated as independent: a slight overestimate of σ
  return m;
}

/// @p runs cache renders of @p cacheSpp spp against one path-traced image of @p pathSpp spp.
CacheBias measure(const RenderScene& scene, int runs, int cacheSpp, int pathSpp) {
  const IntegratorOptions io;  // the renderer's defaults
  CacheBias b;
  b.path = greyMean(test::renderPath(scene, io, pathSpp, 1).film, b.pathSe);
  std::vector<double> m;
  for (int r = 0; r < runs; ++r) {
    IrradianceCacheIntegrator ic(io, IrradianceCacheSettings());
    ic.preprocess(scene);
    const auto run = test::renderWith(ic, scene, cacheSpp, 100 + uint64_t(r));
    EXPECT_EQ(run.stats.nonFinite, 0u);
    double se;
    m.push_back(greyMean(run.film, se));
  }
  for (double v : m) b.cache += v / runs;
  double var = 0;
  for (double v : m) var += (v - b.cache) * (v - b.cache) / (runs - 1);
  b.cacheSe = std::sqrt(var / runs);
  return b;
}

SceneDesc small(const std::string& name, int size) {
  SceneDesc d = loadScene(test::source("scenes/" + name + ".json"));
  d.camera.width = d.camera.height = size;
  return d;
}

void report(const std::string& what, const CacheBias& b) {
  fmt::print("{}: cache {:.5f} ± {:.5f}, path {:.5f} ± {:.5f}: {:+.3f}% ± {:.3f}%\n", what, b.cache, b.cacheSe, b.path,
             b.pathSe, 100 * b.relative(), 100 * b.relativeSe());
}

}  // namespace

// Was −12% with ambient 0 past the last bounce (64 point lights, most light after 3+ bounces).
TEST(IrradianceCacheBias, ManyLightsDefaultsMatchPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("every default irradiance-cache test (they continue paths past the cache)");
  const RenderScene scene(small("many-lights", 16));
  const CacheBias b = measure(scene, 6, 3, 512);
  report("many-lights, no first-shot", b);
  // A CI-sized check (σ ≈ 0.4%: it catches the old −12%, not a 0.5% bias); DISABLED_Measure gives
  // the precise figures of docs/measurements.md.
  EXPECT_LT(std::abs(b.relative()), 0.005 + 3 * b.relativeSe());
  EXPECT_LT(b.relativeSe(), 0.006) << "too noisy to catch a bias of a few percent";
}

/// Measurement over every shipped scene (disabled; --gtest_also_run_disabled_tests). Environment:
///   ICBIAS_SCENES comma-separated names under scenes/ (default: the five of the speed report)
///   ICBIAS_SIZE image side (24), ICBIAS_RUNS cache runs (6), ICBIAS_SPP cache spp (4),
///   ICBIAS_PATH_SPP path spp (1024), ICBIAS_FIRSTSHOT 1: also with a first-shot table (default GL).
TEST(IrradianceCacheBias, DISABLED_Measure) {
  auto env = [](const char* k, const char* d) { return std::string(std::getenv(k) ? std::getenv(k) : d); };
  const std::string list = env("ICBIAS_SCENES", "cornell,many-lights,sierpinski-glossy,fixture-room,office-floor");
  const int size = std::stoi(env("ICBIAS_SIZE", "24")), runs = std::stoi(env("ICBIAS_RUNS", "6"));
  const int spp = std::stoi(env("ICBIAS_SPP", "4")), pathSpp = std::stoi(env("ICBIAS_PATH_SPP", "1024"));
  const bool withTable = env("ICBIAS_FIRSTSHOT", "0") == "1";
  size_t start = 0;
  while (start < list.size()) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    start = comma + 1;
    const SceneDesc desc = small(name, size);
    {
      const RenderScene scene(desc);
      report(name + ", no first-shot", measure(scene, runs, spp, pathSpp));
    }
    if (withTable) {
      const RenderScene scene(desc, test::preprocessDefault(desc));
      report(name + ", first-shot", measure(scene, runs, spp, pathSpp));
    }
  }
}
