// Irradiance at sensor points: NEE to the lights plus one cosine-sampled ray per sample.
#include "render/sensors/sensors.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include "common/lights/photometry.h"
#include "common/materials/bsdf.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/util/interrupt.h"
#include "common/util/progress.h"
#include "render/integrators/common/path_walk.h"
#include "render/lights/light_sampler.h"
#include "render/lights/next_event.h"
#include "render/scene/embree_scene.h"

namespace firstshot {

namespace {

/// Sampler stream of the sensor samples (apart from the camera's stream 0).
constexpr uint64_t kSensorStream = 0x53454e53u;  // "SENS"

/// Per-sensor running sums, in sample order.
struct Sums {
  double e[3] = {0, 0, 0};
  double lux = 0, lux2 = 0;
  uint64_t n = 0;
};

/// The sensor's BSDF: a white Lambertian, f = 1/π on the normal's side.
const BSDF& whiteSensor() {
  static const BSDF white(LambertBRDF{Color(1.0f)});
  return white;
}

/// One sample of E(x, n) with the luminaires of a light sampler that samples them: the sensor is a vertex of a path
/// (a white Lambertian, MIS between its NEE and its cosine ray, which the walk continues from it: @p from(ray, vertex,
/// sampler, info) is the integrator's LiFromSensor()).
template <class FromFn>
Color sampleIrradianceWithLuminaires(const FromFn& from, const RenderScene& scene, const LightSampler& lights,
                                     const Hit& hit, const Frame& frame, Sampler& sampler, uint64_t& rays) {
  const BSDF& white = whiteSensor();
  const Vec3 woLocal(0.0f, 0.0f, 1.0f);
  const LuminaireBoxes& boxes = scene.luminaires();
  PathVertex v;
  v.nee.kept = true;
  v.nee.replaced = true;  // a table's small lights exactly, as at a camera-visible point
  v.nee.inner = boxes.innerWanted(boxes.containing(hit.p), false);  // a box around the sensor is seen as it is
  Color E = kPiF * nextEvent(lights, hit, frame, woLocal, white, v.nee, sampler, rays);
  const Vec3 local = squareToCosineHemisphere(sampler.next2D());
  const Vec3 wi = frame.toWorld(local);
  v.delta = false;
  v.pdf = local.z * kInvPiF;
  v.p = hit.p;
  v.n = hit.ng;
  SampleInfo info;
  E += kPiF * from(Ray(hit.spawnOrigin(wi), wi), v, sampler, &info);  // cos θ/pdf = π
  rays += info.rays;
  return E;
}

/// One sample of E(x, n), W/m² per channel; @p li(ray, sampler, info) is the integrator's Li(), @p from(ray, vertex,
/// sampler, info) its LiFromSensor().
template <class LiFn, class FromFn>
Color sampleIrradiance(const LiFn& li, const FromFn& from, const RenderScene& scene, const LightSampler& lights,
                       const Sensor& sensor, Sampler& sampler, uint64_t& rays) {
  Hit hit;
  hit.p = sensor.p;
  hit.ng = sensor.n;
  // Off a surface the sensor may lie on, as the Embree scene offsets its hits. Not more: shadowRay() aims from the
  // origin spawnOrigin moved along n at the light point and stops only eps + 1e-4·d short of it.
  hit.eps = 1e-5f * std::max({1.0f, std::abs(sensor.p.x), std::abs(sensor.p.y), std::abs(sensor.p.z)});
  const Frame frame(sensor.n);
  if (lights.hasLuminaires()) return sampleIrradianceWithLuminaires(from, scene, lights, hit, frame, sampler, rays);
  const Vec3 woLocal(0.0f, 0.0f, 1.0f);           // the receiving side is the normal's
  const BSDF& white = whiteSensor();
  NeeRequest nee;
  nee.kept = true;
  nee.replaced = true;  // a table's small lights exactly, as at a camera-visible point
  nee.mis = false;      // the cosine ray below never counts the emission it meets first
  Color E = kPiF * nextEvent(lights, hit, frame, woLocal, white, nee, sampler, rays);

  const Vec3 wi = frame.toWorld(squareToCosineHemisphere(sampler.next2D()));
  const Ray ray(hit.spawnOrigin(wi), wi);
  Hit first;
  Color Le(0.0f);
  Color through(1.0f);  // the thin glass panes before the first other hit: their T
  bool glass = false;
  for (Ray r = ray;;) {
    ++rays;
    if (!scene.intersect(r, first)) {  // the sky or environment map, as Li() sees it there: NEE counted it
      Le = through * scene.lights().background(wi);
      break;
    }
    const ThinGlassBSDF* pane = scene.bsdf(scene.material(first)).thinGlass();
    if (!pane) {
      if (!first.onPatch()) Le = through * scene.lights().emitted(first, -wi);
      break;
    }
    glass = true;
    through *= pane->transmittance(std::abs(glm::dot(first.ng, wi)));
    r.tmin = first.t + first.eps;
  }
  SampleInfo info;
  const Color L = li(ray, sampler, &info);
  rays += info.rays;
  // Li() met that emission with weight T/P_T or not at all: L − Le is then unbiased but may be negative.
  E += kPiF * (glass ? L - Le : glm::max(L - Le, Color(0.0f)));  // cos θ/pdf = π
  return E;
}

/// The light sampler of @p integrator (preprocessed), which the sensors' NEE shares.
const LightSampler& sensorLights(const Integrator& integrator) {
  const LightSampler* lights = integrator.lightSampler();
  if (!lights) throw std::logic_error(integrator.name() + ": an integrator for the sensors must have a light sampler");
  return *lights;
}

}  // namespace

void requireSensorIntegrator(const Integrator& integrator) {
  // Light tracing and BDPT splat, the ray bundles need per-pass state: none has a per-ray Li().
  if (!integrator.supportsSensors())
    throw InputError("", "--integrator", fmt::format("{}: sensors support --integrator path or irradiance-cache",
                                                     integrator.name()));
}

void preprocessSensors(Integrator& integrator, const RenderScene& scene, const std::vector<Sensor>& sensors,
                       const SensorOptions& options) {
  requireSensorIntegrator(integrator);
  const uint64_t fill = uint64_t(std::max(1, options.fillSamples));
  // Task i: sensor i's samples 0 .. fill−1, exactly as estimateSensors() draws them, with the light sampler the
  // integrator has built by the time it runs a task.
  const RayTask task = [&](size_t i, const std::function<Color(const Ray&, Sampler&)>& li) {
    const LightSampler& lights = sensorLights(integrator);
    uint64_t rays = 0;
    auto trace = [&](const Ray& ray, Sampler& sampler, SampleInfo*) { return li(ray, sampler); };
    // The cache fills from the sensors' rays; its light sampler has no luminaires, so the vertex is not needed.
    auto fromSensor = [&](const Ray& ray, const PathVertex&, Sampler& sampler, SampleInfo*) { return li(ray, sampler); };
    for (uint64_t s = 0; s < fill; ++s) {
      Sampler sampler = Sampler::make(options.sampler, options.seed, i, s, kSensorStream);
      sampleIrradiance(trace, fromSensor, scene, lights, sensors[i], sampler, rays);
    }
  };
  integrator.preprocessRays(scene, sensors.size(), task, float(options.rayAngle));
}

SensorSummary summarize(const std::vector<SensorResult>& results) {
  SensorSummary s;
  if (results.empty()) return s;
  s.minLux = std::numeric_limits<double>::infinity();
  s.maxLux = -s.minLux;
  double sum = 0;
  for (const SensorResult& r : results) {
    s.minLux = std::min(s.minLux, r.lux);
    s.maxLux = std::max(s.maxLux, r.lux);
    sum += r.lux;
  }
  s.avgLux = sum / double(results.size());
  s.uniformity = s.avgLux > 0 ? s.minLux / s.avgLux : 0.0;
  return s;
}

std::vector<SensorResult> estimateSensors(const Integrator& integrator, const RenderScene& scene,
                                          const std::vector<Sensor>& sensors, const SensorOptions& options,
                                          SensorStats* stats) {
  requireSensorIntegrator(integrator);
  const LightSampler& lights = sensorLights(integrator);
  auto li = [&](const Ray& ray, Sampler& sampler, SampleInfo* info) { return integrator.Li(ray, sampler, info); };
  auto fromSensor = [&](const Ray& ray, const PathVertex& from, Sampler& sampler, SampleInfo* info) {
    return integrator.LiFromSensor(ray, from, sampler, info);
  };
  std::vector<Sums> sums(sensors.size());
  std::atomic<uint64_t> rays{0}, nonFinite{0};
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const int batch = std::max(1, options.batch);
  Comm& comm = options.comm ? *options.comm : serialComm();

  auto pass = [&](uint64_t s0, uint64_t s1, Progress& progress) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, sensors.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
        enableFlushToZero();
        uint64_t localRays = 0, bad = 0;
        for (size_t i = r.begin(); i < r.end(); ++i) {
          if (interrupted()) break;
          if (!comm.mine(i)) continue;
          Sums& acc = sums[i];
          for (uint64_t s = s0; s < s1; ++s) {
            Sampler sampler = Sampler::make(options.sampler, options.seed, i, s, kSensorStream);
            Color E = sampleIrradiance(li, fromSensor, scene, lights, sensors[i], sampler, localRays);
            if (!isFinite(E)) {
              ++bad;
              E = Color(0.0f);
            }
            const double lux = photometry::lux(E, options.efficacy);
            for (int c = 0; c < 3; ++c) acc.e[c] += double(E[c]);
            acc.lux += lux;
            acc.lux2 += lux * lux;
            ++acc.n;
          }
          progress.advance(s1 - s0);
        }
        rays += localRays;
        nonFinite += bad;
      });
    });
    throwIfInterrupted("no output written");
  };

  uint64_t taken = 0;
  if (options.timeLimit > 0) {
    Progress progress = Progress::timed("sensors", options.timeLimit, options.quiet);
    do {
      pass(taken, taken + uint64_t(batch), progress);
      taken += uint64_t(batch);
    } while (!comm.any(comm.root() && seconds() >= options.timeLimit));  // rank 0's clock decides
    progress.finish();
  } else {
    const uint64_t total = uint64_t(std::max(1, options.samples));
    Progress progress("sensors", total * sensors.size(), options.quiet);
    while (taken < total) {  // in batches, so that an interruption is noticed soon
      const uint64_t next = std::min(total, taken + uint64_t(batch) * 16);
      pass(taken, next, progress);
      taken = next;
    }
    progress.finish();
  }

  // Rank 0 receives the other ranks' sensors.
  ByteWriter out;
  for (size_t i = 0; i < sensors.size(); ++i)
    if (comm.mine(i) && !comm.root()) out.put(sums[i]);
  const std::vector<Bytes> all = comm.gather(out.bytes());
  for (size_t r = 1; r < all.size(); ++r) {
    ByteReader in(all[r]);
    for (size_t i = 0; i < sensors.size(); ++i)
      if (comm.owner(i) == int(r)) sums[i] = in.get<Sums>();
  }
  rays = comm.sum(rays), nonFinite = comm.sum(nonFinite);

  std::vector<SensorResult> results(sensors.size());
  for (size_t i = 0; i < sensors.size(); ++i) {
    const Sums& acc = sums[i];
    SensorResult& r = results[i];
    const double n = double(acc.n);
    r.samples = acc.n;
    r.irradiance = Color(float(acc.e[0] / n), float(acc.e[1] / n), float(acc.e[2] / n));
    r.lux = acc.lux / n;
    const double var = n > 1 ? std::max(0.0, (acc.lux2 - acc.lux * acc.lux / n) / (n - 1)) : 0.0;
    r.stderrLux = std::sqrt(var / n);
  }
  if (stats) {
    stats->samples = taken;
    stats->rays = rays;
    stats->nonFinite = nonFinite;
    stats->seconds = seconds();
  }
  return results;
}

}  // namespace firstshot
