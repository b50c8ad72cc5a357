// The deterministic render loop of splatting integrators.
#include "render/loop/splat_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <stdexcept>

#include "common/sampling/rng.h"
#include "common/util/progress.h"
#include "render/loop/adaptive_sampling.h"
#include "render/output/film_exchange.h"
#include "render/scene/embree_scene.h"

namespace firstshot {

namespace {

/// Every rank's chunks of splats to every rank (@p splats holds this rank's chunks on entry, all on exit).
void exchangeSplats(Comm& comm, std::vector<std::vector<Splat>>& splats) {
  if (comm.size() == 1) return;
  ByteWriter out;
  for (size_t c = 0; c < splats.size(); ++c)
    if (comm.mine(c)) out.putVector(splats[c]);
  const std::vector<Bytes> all = comm.allGather(out.bytes());
  for (int r = 0; r < comm.size(); ++r) {
    if (r == comm.rank()) continue;
    ByteReader in(all[size_t(r)]);
    for (size_t c = 0; c < splats.size(); ++c)
      if (comm.owner(c) == r) splats[c] = in.getVector<Splat>();
  }
}

/// The stream of a pixel's k-th extra camera sample of a pass (k ≥ 1; the first takes stream 0).
constexpr uint64_t kExtraStream = 0xada0000;

/// One pass: the particles' splats summed in particle order, then one film sample per pixel. With
/// several ranks, each traces the particle chunks and renders the image rows dealt to it; the
/// splats are exchanged, so every rank sums all of them in the same order.
/// With @p adaptive (the counts of the camera side's samples so far, @p target those to reach, row-major; an
/// adaptive render), pixel p's film sample adds the mean of target[p] − its count camera-side estimates (Li: light
/// tracing's path tracer at a mirror or glass; BDPT's adds nothing), each added to @p adaptive as a sample.
/// @return false if cancelled on any rank (the film is then untouched).
bool splatPass(const SplattingIntegrator& integrator, const Camera& camera, Film& film, const RenderOptions& options,
               uint64_t pass, tbb::task_arena& arena, std::atomic<uint64_t>& rays, std::atomic<uint64_t>& nonFinite,
               Comm& comm, Film* adaptive = nullptr, const std::vector<uint32_t>* target = nullptr) {
  const int w = camera.width(), h = camera.height();
  const uint64_t jitterSeed = options.jitterSeed.value_or(options.seed);
  const uint64_t n = integrator.particlesPerPass(camera);
  const size_t chunks = size_t((n + kSplatChunk - 1) / kSplatChunk);
  std::vector<std::vector<Splat>> splats(chunks);
  std::atomic<bool> cancelled{false};
  auto stop = [&] { return options.cancel && options.cancel->load(std::memory_order_relaxed); };
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks, 1), [&](const tbb::blocked_range<size_t>& r) {
      enableFlushToZero();
      for (size_t c = r.begin(); c < r.end(); ++c) {
        if (!comm.mine(c)) continue;
        if (stop()) {
          cancelled = true;
          continue;
        }
        uint64_t chunkRays = 0;
        integrator.splatParticles(camera, options.seed, jitterSeed, options.sampler, pass, c * kSplatChunk,
                                  std::min(n, (c + 1) * kSplatChunk), splats[c], chunkRays);
        rays += chunkRays;
      }
    });
  });
  if (comm.any(cancelled)) return false;
  exchangeSplats(comm, splats);

  std::vector<Vec3d> image(size_t(w) * size_t(h), Vec3d(0.0));
  uint64_t badSplats = 0;
  for (const std::vector<Splat>& chunk : splats)  // fixed order: the sums do not depend on the threads
    for (const Splat& s : chunk) {
      if (isFinite(s.L)) image[s.pixel] += Vec3d(s.L);
      else ++badSplats;
    }
  if (comm.root()) nonFinite += badSplats;  // every rank sums every splat
  splats.clear();

  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& r) {
      enableFlushToZero();
      uint64_t rowRays = 0, rowBad = 0;
      for (int y = r.begin(); y < r.end(); ++y) {
        if (!comm.mine(uint64_t(y))) continue;  // another rank's row
        for (int x = 0; x < w; ++x) {
          const uint64_t pixel = uint64_t(y) * uint64_t(w) + uint64_t(x);
          const uint32_t m = target ? std::max(1u, (*target)[pixel] - adaptive->samples(x, y)) : 1u;
          Color sum(0.0f);
          SampleInfo first;
          for (uint32_t k = 0; k < m; ++k) {
            const uint64_t stream = k == 0 ? 0 : kExtraStream + k;
            Sampler sampler = Sampler::make(options.sampler, options.seed, pixel, pass, stream);
            const Vec2 jitter = cameraJitter(sampler, options.sampler, options.seed, jitterSeed, pixel, pass, stream);
            SampleInfo info;
            Color L = integrator.Li(camera.generateRay(float(x) + jitter.x, float(y) + jitter.y), sampler, &info);
            rowRays += info.rays;
            if (!isFinite(L)) ++rowBad, L = Color(0.0f);
            if (adaptive) adaptive->add(x, y, L, info.albedo, info.normal);
            sum += L;
            if (k == 0) first = info;
          }
          film.add(x, y, Color(image[pixel]) + sum / float(m), first.albedo, first.normal);
        }
      }
      rays += rowRays;
      nonFinite += rowBad;
    });
  });
  return true;
}

}  // namespace

RenderStats renderSplatting(const SplattingIntegrator& integrator, const Camera& camera, Film& film,
                            const RenderOptions& options) {
  Comm& comm = options.comm ? *options.comm : serialComm();
  std::vector<PixelRect> mine;  // this rank's image rows
  for (int y = 0; y < camera.height(); ++y)
    if (comm.mine(uint64_t(y))) mine.push_back({0, y, camera.width(), y + 1});
  const uint64_t pixels = uint64_t(camera.width()) * uint64_t(camera.height());
  std::atomic<uint64_t> rays{0}, nonFinite{0};
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  if (options.skipTaken)  // a splat pass adds to every pixel: the film must hold whole passes
    for (const uint32_t c : film.sums().count)
      if (c != uint32_t(options.firstSample))
        throw std::invalid_argument("renderSplatting: resuming a film that does not hold firstSample samples everywhere");
  RenderStats stats;
  const bool timed = options.timeLimit > 0;
  const int spp = std::max(1, options.spp);
  Progress progress = timed ? Progress::timed("render", options.timeLimit, options.quiet)
                            : Progress("render", pixels * uint64_t(spp), options.quiet);
  // Adaptive (not with afterPass): after kAdaptiveBase passes each pixel's camera side takes, beside its one
  // estimate a pass, its share of as many again by its estimated error (render/loop/adaptive_sampling.h), kept
  // apart from the particles' in `cameraSide` (a pixel's neighbours there: the two beside it in its row, the rank's
  // unit): where the camera sees a mirror or glass the path tracer's estimate is most of a light tracer's error.
  const bool adaptive = options.adaptive && !options.afterPass;
  std::optional<Film> cameraSide;
  if (adaptive) cameraSide.emplace(camera.width(), camera.height());
  std::vector<uint64_t> rowIndex;
  for (const PixelRect& r : mine) rowIndex.push_back(uint64_t(r.y0));
  int s = options.firstSample, round = 0;
  while (true) {
    std::vector<uint32_t> target;
    if (adaptive && s >= options.firstSample + kAdaptiveBase)
      target = adaptiveTargets(*cameraSide, mine, rowIndex, comm, options.seed, round++, kAdaptiveExtras * double(pixels));
    if (!splatPass(integrator, camera, film, options, uint64_t(s), arena, rays, nonFinite, comm,
                   adaptive ? &*cameraSide : nullptr, target.empty() ? nullptr : &target)) {
      stats.cancelled = true;
      break;
    }
    ++s;
    if (options.afterPass) collectFilm(comm, film, mine), options.afterPass(s);
    progress.advance(pixels);
    if (timed ? comm.any(comm.root() && seconds() >= options.timeLimit)  // rank 0's clock decides
              : s - options.firstSample >= spp)
      break;
  }
  progress.finish();
  collectFilm(comm, film, mine);
  rays = comm.sum(rays), nonFinite = comm.sum(nonFinite);
  stats.spp = s - options.firstSample;
  stats.seconds = seconds();
  stats.rays = rays;
  stats.nonFinite = nonFinite;
  stats.cameraSamples = pixels * uint64_t(stats.spp);
  return stats;
}

}  // namespace firstshot
