// The deterministic render loop of splatting integrators.
#include "render/loop/splat_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>

#include "common/sampling/rng.h"
#include "common/util/progress.h"
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

/// One pass: the particles' splats summed in particle order, then one film sample per pixel. With
/// several ranks, each traces the particle chunks and renders the image rows dealt to it; the
/// splats are exchanged, so every rank sums all of them in the same order.
/// @return false if cancelled on any rank (the film is then untouched).
bool splatPass(const SplattingIntegrator& integrator, const Camera& camera, Film& film, const RenderOptions& options,
               uint64_t pass, tbb::task_arena& arena, std::atomic<uint64_t>& rays, std::atomic<uint64_t>& nonFinite,
               Comm& comm) {
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
          Sampler sampler = Sampler::make(options.sampler, options.seed, pixel, pass);
          const Vec2 jitter = cameraJitter(sampler, options.sampler, options.seed, jitterSeed, pixel, pass);
          SampleInfo info;
          Color L = integrator.Li(camera.generateRay(float(x) + jitter.x, float(y) + jitter.y), sampler, &info);
          rowRays += info.rays;
          if (!isFinite(L)) ++rowBad, L = Color(0.0f);
          film.add(x, y, Color(image[pixel]) + L, info.albedo, info.normal);
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
  int s = options.firstSample;
  while (true) {
    if (!splatPass(integrator, camera, film, options, uint64_t(s), arena, rays, nonFinite, comm)) {
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
