// Irradiance caching around the render: light classification, the cache file, the two-pass
// fill, and the record image.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>

#include "common/lights/small_light_rule.h"
#include "common/sampling/rng.h"
#include "common/util/comm.h"
#include "common/util/error.h"
#include "common/util/interrupt.h"
#include "common/util/progress.h"
#include "render/integrators/irradiance_cache/cache_file.h"
#include "render/integrators/irradiance_cache/context.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/scene/camera.h"
#include "render/scene/embree_scene.h"

namespace firstshot {

namespace {

/// preprocessFor: about one level-0 record in this many is gathered a second time (its own noise, for the pilot; one
/// in eight read the classroom's as 0.039 and 0.022 for two seeds, and its choice with them).
constexpr int kSpreadEvery = 2;

/// preprocessRays: rays a fill task may trace before its misses take paths instead of making records. A
/// sensor inside a closed object (a grid crossing furniture) filled the inside with small records, 5 M
/// rays per task on many-lights where a task in the open took under 0.7 M.
constexpr uint64_t kRayTaskBudget = uint64_t(1) << 20;
constexpr size_t kMaxBatch = 256;           ///< fill tasks merged at once at most

/// The next batch's size after one of @p batch tasks whose records were @p made, @p duplicates of them covered at the
/// merge by an earlier task's (work done twice: each task of a batch traces against the cache as the batch found it).
/// Doubled while at most a quarter were duplicates, halved where more than half were, kept otherwise, and kept where
/// no task of it looked the cache up (@p looked: pixels that see nothing say nothing of the next ones). The first
/// pixels' records make the deeper levels' all over the room, and batches doubled regardless (1, 2, 4, ...) made them
/// once a task: McGuire's box with its table at 2048 rays per record, whose first 15 pixels see nothing, made them 16
/// times over, 46.1 Mrays for the 11.2 its records took one task at a time. It depends on the records alone, as they
/// do not on the threads: the same batches on every machine.
size_t nextBatch(size_t batch, size_t made, size_t duplicates, bool looked) {
  if (!looked) return batch;
  if (4 * duplicates <= made) return std::min(2 * batch, kMaxBatch);
  if (2 * duplicates > made) return std::max<size_t>(1, batch / 2);
  return batch;
}

/// Pixel indices coarse to fine: every 16th pixel of every 16th row, then the new pixels of the
/// grids of spacing 8, 4, 2 and 1, each in row order.
std::vector<uint32_t> fillOrder(int width, int height) {
  std::vector<uint32_t> order;
  order.reserve(size_t(width) * size_t(height));
  for (int s = 16; s >= 1; s /= 2)
    for (int y = 0; y < height; y += s)
      for (int x = 0; x < width; x += s)
        if (s == 16 || x % (2 * s) != 0 || y % (2 * s) != 0) order.push_back(uint32_t(y) * uint32_t(width) + uint32_t(x));
  return order;
}

/// The angle one pixel of @p cam spans vertically at the image centre, rad.
float pixelAngleOf(const CameraDesc& cam) {
  return float(2.0 * std::tan(glm::radians(cam.fovYDeg) * 0.5) / std::max(1, cam.height));
}

}  // namespace

void IrradianceCacheIntegrator::preprocess(const RenderScene& scene) { fillFor(scene, scene.desc().camera); }

void IrradianceCacheIntegrator::preprocessFor(const RenderScene& scene, const CameraDesc& camera) {
  spreadEvery_ = kSpreadEvery;  // some records gathered twice: their own noise (perturbPreprocessing)
  fillFor(scene, camera);
  spreadEvery_ = 0;
  pathOnMiss_ = settings_.twoPass;  // the pilot's finer picture over these records: a sample they miss takes one path
}

void IrradianceCacheIntegrator::fillFor(const RenderScene& scene, const CameraDesc& cameraDesc) {
  setup(scene);
  pixelAngle_ = pixelAngleOf(cameraDesc);
  if (!settings_.twoPass) return;
  const Camera camera(cameraDesc);
  const uint32_t width = uint32_t(camera.width());
  const std::vector<uint32_t> order = fillOrder(camera.width(), camera.height());
  // The render's own camera samples 0 .. fillSamples−1 of the pixel (renderer.cpp), so that the
  // render finds every record those samples need.
  fill(order.size(), [&](size_t i, const std::function<Color(const Ray&, Sampler&)>& li) {
    const uint32_t pixel = order[i];
    for (int k = 0; k < std::max(1, settings_.fillSamples); ++k) {
      Sampler sampler = Sampler::make(settings_.sampler, settings_.seed, pixel, uint64_t(k));
      const Vec2 jitter = sampler.next2D();
      li(camera.generateRay(float(pixel % width) + jitter.x, float(pixel / width) + jitter.y), sampler);
    }
  });
  frozen_ = true;
  // A render sample the records do not cover (a sub-pixel position or a bounce the fill's samples did not meet) takes
  // one path from there (no bias), not a record private to that sample: its hundreds of rays, and the deeper levels'
  // private records below it, served one sample only (the classroom at 64 x 64, 60 s: 414 samples per pixel with
  // them, 3,277 with paths, noise 0.073 against 0.052). Ward's private records with missRecords.
  pathOnMiss_ = !settings_.missRecords;
}

void IrradianceCacheIntegrator::preprocessRays(const RenderScene& scene, size_t tasks, const RayTask& task,
                                               float rayAngle) {
  setup(scene);
  pixelAngle_ = rayAngle;
  if (!settings_.twoPass) return;
  // With luminaires the sensors' rays are path traced past the sensor (LiFromSensor): no records to fill.
  if (luminaires_) {
    frozen_ = true;
    return;
  }
  pathOnMiss_ = true;
  taskRayBudget_ = kRayTaskBudget;
  fill(tasks, task);
  taskRayBudget_ = 0;
  frozen_ = true;
}

void IrradianceCacheIntegrator::setup(const RenderScene& scene) {
  if (!(settings_.accuracy > 0.0f) || settings_.samples < 1 || settings_.bounces < 0 || !(settings_.footprintMin >= 0.0f) ||
      !(settings_.footprintMax >= settings_.footprintMin))
    throw std::invalid_argument("irradiance cache: invalid settings");
  scene_ = &scene;
  frozen_ = false;
  pathOnMiss_ = false;
  taskRayBudget_ = 0;
  loaded_ = 0;
  fillSeconds_ = 0;
  fillRounds_ = 0;
  fillCutAt_ = 0;
  fillTasks_ = 0;
  fillRays_ = 0;
  privateRecords_ = 0;
  madeRecords_ = 0;
  duplicateRecords_ = 0;
  missPaths_ = 0;
  exchangeBytes_ = 0;
  exchangeSeconds_ = 0;
  if (!settings_.twoPass && options_.comm && options_.comm->size() > 1)
    throw InputError("", "--one-pass",
                     "the one-pass irradiance cache depends on the thread schedule and cannot be split over MPI ranks; "
                     "use the two-pass fill (the default)");
  firstShot_.build(scene);
  // The luminaires' light (exit patches, specular light, the light straight from their lights) is direct light, taken
  // by NEE at every shaded point: never gathered by the records' rays (luminaires.cpp). Under LightStrategy::Tree only,
  // as in the path tracer, and where every luminaire holds glass, a mirror or a glossy surface (holdsNonLambertian):
  // otherwise their lights are lights.
  const LuminaireBoxes& boxes = scene.luminaires();
  luminaires_ = options_.luminaires && options_.lightSampler == LightStrategy::Tree && !boxes.empty() &&
                std::all_of(boxes.items().begin(), boxes.items().end(),
                            [&](const Luminaire& l) { return holdsNonLambertian(scene, l); });
  IntegratorOptions walk = options_;
  walk.luminaires = luminaires_;
  continuation_.build(scene, firstShot_, walk);
  if (!(settings_.patchNee >= 0.0f)) throw std::invalid_argument("irradiance cache: invalid settings");

  // Large area lights are gathered by the cache (§5); every other light is direct light.
  const LightSet& lights = scene.lights();
  const size_t n = lights.lights().size();
  gathered_.assign(n, 0);
  direct_.assign(n, 1);
  gatheredEmitter_.assign(lights.emitterMeshes().size(), 0);
  for (size_t l = 0; l < n; ++l) {
    const RenderLight& light = lights.lights()[l];
    if (light.type != LightType::Area || (luminaires_ && boxes.ofLight(uint32_t(l)) >= 0)) continue;
    // A replaced light's first bounce is the table's; a light the table kept (a luminaire's, when its box is not
    // taken here, or one it judged large) is judged by the small-light rule: gathered, a bulb of a few centimetres
    // is met by the records' rays by chance, and its light comes out low and in blotches.
    const bool small = (scene.firstShot() && light.replaced) ||
                       isSmallLight(scene.desc(), light.desc, scene.desc().settings.smallLightMaxSolidAngle);
    if (small) continue;
    gathered_[l] = 1;
    direct_[l] = 0;
    gatheredEmitter_[light.emitter] = 1;
  }
  directLights_.build(scene, firstShot_, options_.lightSampler, scene.firstShot() && settings_.patchNee > 0.0f,
                      options_.lightVisibility, &direct_, true, luminaires_);  // with the sky: direct light too
  // The camera's vertices outside the boxes take the luminaires' lights only where some light leaves a box straight.
  directEvery_ = direct_;
  if (luminaires_)
    for (size_t l = 0; l < n; ++l)
      if (boxes.ofLight(uint32_t(l)) >= 0) directEvery_[l] = 0;

  Vec3d lo, hi;
  scene.desc().bounds(lo, hi);
  boundsLo_ = Vec3(lo);
  boundsHi_ = Vec3(hi);
  pixelAngle_ = pixelAngleOf(scene.desc().camera);
  cache_ = makeCache();

  const std::string& file = settings_.cacheFile;
  if (!file.empty() && std::filesystem::exists(file)) {
    const CacheFileData d = readCacheFile(file, hashScene(scene.desc()), settingsText());
    if (int(d.levels.size()) != cache_->levels()) throw InputError(file, "records", "wrong number of levels (corrupt file)");
    for (int l = 0; l < cache_->levels(); ++l)
      for (IrradianceRecord r : d.levels[size_t(l)]) {
        r.zone = zoneOf(r.p);  // not in the file: the scene's boxes decide it
        cache_->insert(l, r, false);
      }
    loaded_ = cache_->size();
  }
}

void IrradianceCacheIntegrator::fill(size_t tasks, const RayTask& task) {
  const auto start = std::chrono::steady_clock::now();
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  Comm& comm = options_.comm ? *options_.comm : serialComm();

  // One sweep over the pixels; returns the number of records added.
  std::atomic<uint64_t> rays{0};
  bool overLimit = false;  // limitPreprocessRays(): stopped past it, unfit to render
  fillTasks_ = tasks;
  auto pastTime = [&] {  // limitPreprocessSeconds(): one rank alone (several would stop at different batches)
    return fillSecondsLimit_ > 0 && comm.size() == 1 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > fillSecondsLimit_;
  };
  auto sweep = [&](bool shrinkNeighbours) {
    Progress progress(shrinkNeighbours ? "irradiance cache fill" : "irradiance cache fill, gaps", tasks,
                      settings_.quiet || !comm.root());
    size_t added = 0;
    cache_->freeze();
    for (size_t pos = 0, batch = 1, next = 1; pos < tasks; pos += batch, batch = next) {
      // SIGINT/SIGTERM: the fill stops between batches (common/util/interrupt.h). With several ranks
      // only at the exchange, where every rank learns of it, so that none waits for the others.
      if (comm.size() == 1) throwIfInterrupted();
      const size_t count = std::min(batch, tasks - pos);
      std::vector<size_t> mine;  // the batch's tasks dealt to this rank
      for (size_t i = 0; i < count; ++i)
        if (comm.mine(pos + i)) mine.push_back(i);
      // Each task traces its pixel against the cache as it was at the start of the batch,
      // keeping the records it has to make to itself...
      std::vector<MadeRecords> made(count);
      std::vector<uint8_t> looked(count, 0);  // the tasks that looked the cache up
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, mine.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
          enableFlushToZero();
          for (size_t k = r.begin(); k < r.end(); ++k) {
            if (interrupted()) break;  // thrown below, before the merge
            const size_t i = mine[k];
            Context ctx(Context::Mode::Private);
            struct CountRays {  // the task's rays join the fill's count however it ends
              Context& ctx;
              std::atomic<uint64_t>& total;
              ~CountRays() { total += ctx.rays; }
            } countRays{ctx, rays};
            try {
              task(pos + i, [&](const Ray& ray, Sampler& sampler) {
                return radiance(ray, 0, RayKind::Camera, 0.0f, sampler, ctx, nullptr, nullptr);
              });
            } catch (const Interrupted&) {
              break;  // gather() stopped the task; the flag stays set, so it is thrown below (on every rank)
            }
            looked[i] = ctx.lookups > 0;
            if (ctx.overlay)
              for (int l = 0; l < ctx.overlay->levels(); ++l) made[i].push_back(ctx.overlay->records(l));
          }
        });
      });
      if (comm.size() == 1) {
        throwIfInterrupted();
      } else if (const int signal = exchangeRecords(comm, pos, mine, made, looked)) {
        throw Interrupted(signal, "no output written");
      }
      // ...then the records are merged in task order, each unless an earlier one covers it.
      size_t madeHere = 0, duplicates = 0;
      for (const MadeRecords& m : made)
        for (int l = 0; l < int(m.size()); ++l)
          for (const IrradianceRecord& r : m[size_t(l)]) {
            ++madeHere;
            if (cache_->covers(l, r.p, r.n, r.zone)) {
              ++duplicates;
              continue;
            }
            cache_->insert(l, r, settings_.neighbourClamp, shrinkNeighbours);
          }
      added += madeHere - duplicates;
      madeRecords_ += madeHere;
      duplicateRecords_ += duplicates;
      next = nextBatch(count, madeHere, duplicates, std::find(looked.begin(), looked.end(), 1) != looked.end());
      cache_->freeze();  // the next batch's tasks only read it
      progress.advance(count);
      if (fillRayLimit_ > 0 && rays.load() > fillRayLimit_) {
        overLimit = true;
        break;
      }
      if (pastTime()) {  // what is made so far serves; the rest of the pixels take paths
        fillCutAt_ = pos + count;
        break;
      }
    }
    return added;
  };
  // Neighbour clamping may shrink a record that covered an earlier pixel; a second sweep fills
  // such gaps with records that shrink nothing, so afterwards every pixel is covered and a later
  // run from the saved file adds nothing (its first sweep finds nothing to do).
  fillRounds_ = 1;
  if (sweep(true) > 0 && settings_.neighbourClamp && !overLimit && fillCutAt_ == 0) {
    fillRounds_ = 2;
    sweep(false);
  }
  // Rebuild the octrees from the final records in order, exactly as reading the file does.
  rebuildCache([](int, size_t, IrradianceRecord&) {});
  fillSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fillRays_ = rays.load();
}

void IrradianceCacheIntegrator::perturbPreprocessing(uint64_t seed) {
  if (!cache_ || cache_->levels() == 0) return;
  // The records' relative noise, their squares summed (the bright records, which make most of the picture, weigh most).
  double spread2 = 0.0, value2 = 0.0;
  for (const IrradianceRecord& r : cache_->records(0))
    if (r.spread.x >= 0.0f) {
      spread2 += double(luminance(r.spread)) * double(luminance(r.spread));
      value2 += double(luminance(r.E)) * double(luminance(r.E));
    }
  if (!(value2 > 0.0)) return;
  const double s = std::sqrt(spread2 / value2);
  rebuildCache([&](int level, size_t i, IrradianceRecord& r) {
    if (level > 0) return;
    // A normal number by Box–Muller from two keyed uniforms.
    const double u1 = 1.0 - bitsToUnitDouble(hashKeys(seed, uint64_t(i), 0u));
    const double u2 = bitsToUnitDouble(hashKeys(seed, uint64_t(i), 1u));
    const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    r.E = glm::max(r.E * float(1.0 + z * s), Color(0.0f));
  });
}

void IrradianceCacheIntegrator::rebuildCache(const std::function<void(int, size_t, IrradianceRecord&)>& edit) {
  auto rebuilt = makeCache();
  for (int l = 0; l < cache_->levels(); ++l) {
    std::vector<IrradianceRecord> records = cache_->records(l);
    for (size_t i = 0; i < records.size(); ++i) {
      edit(l, i, records[i]);
      rebuilt->insert(l, records[i], false);
    }
  }
  rebuilt->freeze();  // read only from here
  cache_ = std::move(rebuilt);
}

int IrradianceCacheIntegrator::exchangeRecords(Comm& comm, size_t pos, const std::vector<size_t>& mine,
                                               std::vector<MadeRecords>& made, std::vector<uint8_t>& looked) {
  const auto start = std::chrono::steady_clock::now();
  // Per rank: its interrupt signal (0: none), then per task of its own, in order: the task's
  // number, whether it looked the cache up, its levels, and each level's records in the order the task made them.
  // The flag is read once: set after the tasks ended, it leaves their records complete.
  const int32_t mySignal = int32_t(interruptSignal());
  ByteWriter out;
  out.put<int32_t>(mySignal);
  if (mySignal == 0)
    for (const size_t i : mine) {
      out.put<uint64_t>(pos + i);
      out.put<uint8_t>(looked[i]);
      out.put<uint32_t>(uint32_t(made[i].size()));
      for (const auto& level : made[i]) out.putVector(level);
    }
  const uint64_t before = comm.bytesSent();
  const std::vector<Bytes> all = comm.allGather(out.bytes());
  exchangeBytes_ += comm.bytesSent() - before;
  int signal = 0;
  for (int r = 0; r < comm.size(); ++r) {
    ByteReader in(all[size_t(r)]);
    const int32_t s = in.get<int32_t>();
    if (s != 0 && signal == 0) signal = s;
    if (s != 0 || r == comm.rank()) continue;
    for (size_t i = 0; i < made.size(); ++i) {
      if (comm.owner(pos + i) != r) continue;
      if (in.get<uint64_t>() != pos + i) throw std::runtime_error("irradiance cache: exchange between ranks out of order");
      looked[i] = in.get<uint8_t>();
      made[i].resize(in.get<uint32_t>());
      for (auto& level : made[i]) level = in.getVector<IrradianceRecord>();
    }
    if (!in.done()) throw std::runtime_error("irradiance cache: exchange between ranks out of order");
  }
  exchangeSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return signal;
}

void IrradianceCacheIntegrator::saveCache(const std::string& path) const {
  if (!scene_ || !cache_) throw std::logic_error("saveCache before preprocess");
  CacheFileData d;
  d.sceneHash = hashScene(scene_->desc());
  d.settings = settingsText();
  for (int l = 0; l < cache_->levels(); ++l) d.levels.push_back(cache_->records(l));
  writeCacheFile(path, d);
}

void IrradianceCacheIntegrator::writeRecordImage(const Film& film, const std::string& path, float exposure) const {
  const CameraDesc& c = scene_->desc().camera;
  const int w = film.width(), h = film.height();
  std::vector<uint8_t> mark(size_t(w) * size_t(h), 0);
  // The camera's projection (the inverse of Camera::generateRay).
  const Vec3d fwd = glm::normalize(c.lookAt - c.position), right = glm::normalize(glm::cross(fwd, c.up));
  const Vec3d up = glm::cross(right, fwd);
  const double tanHalf = std::tan(glm::radians(c.fovYDeg) * 0.5), aspect = double(w) / double(h);
  for (const IrradianceRecord& r : cache_->records(0)) {
    const Vec3d v = Vec3d(r.p) - c.position;
    const double z = glm::dot(v, fwd);
    if (!(z > 0)) continue;
    const double sx = glm::dot(v, right) / (z * tanHalf * aspect), sy = glm::dot(v, up) / (z * tanHalf);
    const int px = int(std::floor((sx + 1.0) * 0.5 * w)), py = int(std::floor((1.0 - sy) * 0.5 * h));
    if (px < 0 || py < 0 || px >= w || py >= h) continue;
    // Marked only where the camera sees the record's point itself (not through a mirror).
    const double dist = glm::length(v);
    Hit hit;
    if (!scene_->intersect(Ray(Vec3(c.position), Vec3(v / dist)), hit) || hit.t < float(dist) * 0.999f - 1e-4f) continue;
    mark[size_t(py) * size_t(w) + size_t(px)] = 1;
  }
  Film out(w, h);
  const Color blue(0.0f, 0.0f, std::max(1.0f, std::exp2(-exposure)));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      out.add(x, y, mark[size_t(y) * size_t(w) + size_t(x)] ? blue : Color(film.mean(x, y)), Color(0.0f), Vec3(0.0f));
  out.write(path, false, exposure);
}

}  // namespace firstshot
