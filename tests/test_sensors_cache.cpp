// The irradiance cache at sensors (render/sensors/sensors.h preprocessSensors → Integrator::preprocessRays):
// its records are filled from the sensors' own first samples, so those samples find them; results do not
// depend on the thread count; and the grid's mean illuminance agrees with path tracing's. As in
// test_irradiance_cache_bias, records are shared by all sensors of a run, so runs (independent seeds, each
// with its own cache) are the independent samples of the cache's mean; the target bias bound is 0.5%.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <vector>

#include "common/formats/load_scene.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/sensors/sensors.h"
#include "render_util.h"
#include "test_util.h"

using namespace firstshot;

namespace {

/// A scene and a grid on its floor, with the integrator options of the sensor mode (render/cli/render_command.cpp:
/// the sensor is vertex 0, so the depth counts from its rays' first hits).
struct Grid {
  SceneDesc desc;
  RenderScene scene;
  std::vector<Sensor> sensors;
  IntegratorOptions io;
  Grid(const std::string& name, const std::string& spec)
      : desc(loadScene(test::source("scenes/" + name + ".json"))), scene(desc),
        sensors(gridOnQuad(desc, spec).sensors) {
    io.maxDepth = std::max(0, desc.settings.maxDepth - 1);
  }
  /// Mean illuminance over the grid and its standard error (sensors independent).
  static double mean(const std::vector<SensorResult>& r, double* se = nullptr) {
    double m = 0, v = 0;
    for (const SensorResult& x : r) m += x.lux, v += x.stderrLux * x.stderrLux;
    if (se) *se = std::sqrt(v) / double(r.size());
    return m / double(r.size());
  }
};

std::vector<SensorResult> cacheEstimate(const Grid& g, SensorOptions so, int threads, IrradianceCacheStats* stats = nullptr) {
  IrradianceCacheSettings s;
  s.threads = threads;
  IrradianceCacheIntegrator ic(g.io, s);
  so.threads = threads;
  preprocessSensors(ic, g.scene, g.sensors, so);
  const auto r = estimateSensors(ic, g.scene, g.sensors, so);
  if (stats) *stats = ic.stats();
  return r;
}

}  // namespace

// The fill traces the estimate's own first samples: with as many samples as the fill, the estimate makes no
// record of its own; one or two threads give the same records and the same numbers.
TEST(SensorsCache, FillCoversItsSamplesAndThreadCountDoesNotMatter) {
  const Grid g("cornell-metre", "floor,4,1.5");
  ASSERT_EQ(g.sensors.size(), 16u);
  SensorOptions so;
  so.samples = so.fillSamples = 3;
  so.batch = 2;
  IrradianceCacheStats one, two;
  const auto a = cacheEstimate(g, so, 1, &one);
  const auto b = cacheEstimate(g, so, 2, &two);
  EXPECT_GT(one.records, 0u);
  EXPECT_EQ(one.records, two.records);
  EXPECT_EQ(one.privateRecords, 0u);
  EXPECT_EQ(one.missPaths, 0u) << "a fill sample missed its records";
  so.samples = 16;  // later samples meet points the fill did not: one path each, still the same for any thread count
  const auto c = cacheEstimate(g, so, 1, &one), d = cacheEstimate(g, so, 2, &two);
  EXPECT_GT(one.missPaths, 0u);
  EXPECT_EQ(one.missPaths, two.missPaths);
  for (size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i].lux, d[i].lux) << i;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].lux, b[i].lux) << i;
    EXPECT_EQ(a[i].irradiance, b[i].irradiance) << i;
    EXPECT_GT(a[i].lux, 0.0);
  }
}

// cornell-metre, sensors 1 m under the ceiling facing down: they see no light directly, only the room's
// reflected light, much of it through the cache's records. The grid's mean illuminance with the cache within
// 0.5% + 3σ of path tracing's.
TEST(SensorsCache, CornellCeilingGridMatchesPathTracing) {
  FIRSTSHOT_STATISTICS_ONLY("SensorsCache.FillCoversItsSamplesAndThreadCountDoesNotMatter");
  const Grid g("cornell-metre", "ceiling,1,1.1");
  ASSERT_EQ(g.sensors.size(), 25u);
  ASSERT_LT(g.sensors[0].n.y, -0.99f);
  SensorOptions so;
  so.samples = 8192;
  auto path = makeIntegrator("path", g.io);
  preprocessSensors(*path, g.scene, g.sensors, so);
  double pathSe;
  const double pathMean = Grid::mean(estimateSensors(*path, g.scene, g.sensors, so), &pathSe);

  constexpr int kRuns = 6;
  so.samples = 1024;
  std::vector<double> m;
  for (int r = 0; r < kRuns; ++r) {
    so.seed = 100 + uint64_t(r);
    m.push_back(Grid::mean(cacheEstimate(g, so, 0)));
  }
  double cache = 0, var = 0;
  for (double v : m) cache += v / kRuns;
  for (double v : m) var += (v - cache) * (v - cache) / (kRuns - 1);
  const double se = std::hypot(pathSe, std::sqrt(var / kRuns));
  fmt::print("cornell-metre ceiling grid: cache {:.4f} lx, path {:.4f} ± {:.4f} lx: {:+.3f}% ± {:.3f}%\n", cache,
             pathMean, pathSe, 100 * (cache - pathMean) / pathMean, 100 * se / pathMean);
  EXPECT_LT(std::abs(cache - pathMean), 0.005 * pathMean + 3 * se);
  EXPECT_LT(se, 0.006 * pathMean) << "too noisy to catch a bias of a few percent";
}
