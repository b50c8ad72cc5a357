// Patch NEE in the irradiance cache's primary method (IrradianceCacheSettings::patchNee): the
// variance of a record's irradiance E and the time per record, at camera-visible points of a
// scene with a first-shot table, for several NEE rates (samples per hemisphere ray; 0 = off).
// A plain program that prints a Markdown table.
//
// Each point (the first hit of the camera ray through the centre of each cell of a G × G grid
// over the image) gets R records, each from its own seed (computeRecord at level 0, with
// --bounces B cached levels below it and path continuation past them, as in a render; with
// --fill W the cache is first filled by a two-pass fill of the camera at W pixels wide, so that
// the deeper levels are mostly interpolated, as in a render). Per rate:
// the mean over points of var(E)/mean(E)² (relative variance of one record, channel mean), the
// mean time per record, and the efficiency against the rays alone, (var·time)_off / (var·time),
// per point and then as the geometric mean over points.
//
// Usage: bench_ic_patch_nee SCENE.json TABLE.fsd [--records R] [--grid G] [--samples N] [--bounces B]
//                           [--fill W] [--rates r1,r2,...]
#include <fmt/core.h>

#include <ctime>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"

using namespace firstshot;

namespace {

/// CPU time of this thread, s (the records are computed on it; robust against other load on the machine).
double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Point {
  Hit hit;
  Vec3 n{0.0f};
};

/// Camera-visible diffuse points: first hits through the centres of a G × G grid of image cells.
std::vector<Point> visiblePoints(const RenderScene& scene, int G) {
  const Camera camera(scene.desc().camera);
  std::vector<Point> points;
  for (int gy = 0; gy < G; ++gy)
    for (int gx = 0; gx < G; ++gx) {
      const float x = (float(gx) + 0.5f) / float(G) * float(camera.width());
      const float y = (float(gy) + 0.5f) / float(G) * float(camera.height());
      const Ray ray = camera.generateRay(x, y);
      Hit hit;
      if (!scene.intersect(ray, hit) || !hit.onPatch()) continue;
      const BSDF& bsdf = scene.bsdf(scene.material(hit));
      if (bsdf.hasDelta() || maxComponent(bsdf.diffuseAlbedo()) <= 0.0f) continue;
      const Vec3 wo = -glm::normalize(ray.d);
      points.push_back({hit, glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng});
    }
  return points;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: {} SCENE.json TABLE.fsd [--records R] [--grid G] [--samples N] [--bounces B] [--rates r,...]\n",
               argv[0]);
    return 2;
  }
  int records = 64, grid = 4, samples = 512, bounces = 1, fill = 0;
  std::vector<float> rates = {0.0f, 0.25f, 0.5f, 1.0f, 2.0f};
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--records")) records = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--grid")) grid = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--samples")) samples = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--bounces")) bounces = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--fill")) fill = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--rates")) {
      rates.clear();
      for (const char* p = argv[i + 1]; *p;) {
        char* end;
        rates.push_back(std::strtof(p, &end));
        p = *end == ',' ? end + 1 : end;
      }
    }
  }
  SceneDesc desc = loadScene(argv[1]);
  if (fill > 0) {
    desc.camera.height = std::max(1, desc.camera.height * fill / desc.camera.width);
    desc.camera.width = fill;
  }
  const RenderScene scene(desc, readFirstShot(argv[2]));
  const std::vector<Point> points = visiblePoints(scene, grid);
  fmt::print("{}: {} points, {} records each, {} hemisphere samples, {} cached bounce(s), {}\n\n", argv[1],
             points.size(), records, samples, bounces,
             fill > 0 ? fmt::format("cache filled at {}x{}", desc.camera.width, desc.camera.height) : "empty cache");
  fmt::print("| NEE per ray | mean rel. variance of E | time per record (ms) | efficiency vs off (geo. mean) | "
             "mean E / off |\n|---|---|---|---|---|\n");
  std::vector<double> offVar(points.size()), offTime(points.size()), offMean(points.size());
  for (float rate : rates) {
    IrradianceCacheSettings s;
    s.samples = samples;
    s.bounces = bounces;
    s.footprintMin = 0.0f;
    s.footprintMax = std::numeric_limits<float>::infinity();
    s.patchNee = rate;
    s.twoPass = fill > 0;
    IntegratorOptions io;
    io.maxDepth = desc.settings.maxDepth;
    IrradianceCacheIntegrator ic(io, s);
    ic.preprocess(scene);
    double relVar = 0, time = 0, logEff = 0, meanRatio = 0;
    int used = 0;
    for (size_t k = 0; k < points.size(); ++k) {
      double sum = 0, sum2 = 0;
      const double t0 = threadSeconds();
      for (int r = 0; r < records; ++r) {
        Sampler sampler(99, k, uint64_t(r));
        const IrradianceRecord rec = ic.computeRecord(points[k].hit, points[k].n, 0, sampler);
        const double e = (rec.E.x + rec.E.y + rec.E.z) / 3.0;
        sum += e, sum2 += e * e;
      }
      const double t = (threadSeconds() - t0) / records;
      const double mean = sum / records, var = std::max(0.0, (sum2 - records * mean * mean) / (records - 1));
      if (rate == rates.front()) offVar[k] = var, offTime[k] = t, offMean[k] = mean;
      if (!(mean > 0) || !(var > 0) || !(offVar[k] > 0)) continue;
      ++used;
      relVar += var / (mean * mean);
      time += t;
      logEff += std::log(offVar[k] * offTime[k] / (var * t));
      meanRatio += mean / offMean[k];
    }
    if (used == 0) continue;
    fmt::print("| {} | {:.4f} | {:.2f} | {:.2f} | {:.3f} |\n", rate, relVar / used, 1e3 * time / used,
               std::exp(logEff / used), meanRatio / used);
  }
  return 0;
}
