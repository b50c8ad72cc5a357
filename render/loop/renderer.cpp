// Tiled, deterministic parallel rendering.
#include "render/loop/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "common/sampling/rng.h"
#include "common/util/progress.h"
#include "render/loop/adaptive_sampling.h"
#include "render/loop/splat_renderer.h"
#include "render/output/film_exchange.h"
#include "render/scene/embree_scene.h"

namespace firstshot {

namespace {

struct Tile {
  int x0, y0, x1, y1;
};

std::vector<Tile> makeTiles(int width, int height, int size) {
  std::vector<Tile> tiles;
  for (int y = 0; y < height; y += size)
    for (int x = 0; x < width; x += size) tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});
  return tiles;
}

/// Samples [s0, s1) of every pixel of a tile, in sample order per pixel, by blocks of 4 × 4 pixels
/// (on the image's grid of such blocks: the tiles' sides are multiples of 4), each block one sample
/// index at a time (Integrator::LiBlock). With @p skipTaken, only the samples a pixel does not hold
/// yet. Stops between two sample indices of a block once @p cancel is set (every pixel then holds
/// its first samples, in order): @return false if it did.
/// With @p target (an adaptive round, row-major over the image), pixel p takes the samples from the count it
/// holds to target[p] instead, the block's j-th step being each pixel's j-th sample of the round (its own index,
/// so that a step's camera rays still go as one packet), and only the pixels that take a sample are traced.
bool renderTile(const Integrator& integrator, const Camera& camera, Film& film, const Tile& tile, int s0, int s1,
                uint64_t seed, uint64_t jitterSeed, SamplerMode mode, bool skipTaken, const std::atomic<bool>* cancel,
                const std::vector<uint32_t>* target, uint64_t& rays, uint64_t& nonFinite, uint64_t& samples) {
  constexpr int B = 4;
  for (int by = tile.y0; by < tile.y1; by += B)
    for (int bx = tile.x0; bx < tile.x1; bx += B) {
      const int w = std::min(B, tile.x1 - bx), h = std::min(B, tile.y1 - by), count = B * (h - 1) + w;
      int first[B * B], end[B * B];
      bool inImage[B * B] = {};
      int begin = s1, last = s1;  // the steps: sample indices, or with target the round's j-th samples
      if (target) begin = 0, last = 0;
      for (int k = 0; k < count; ++k) {
        const int x = bx + k % B, y = by + k / B;
        if (k % B >= w) continue;
        inImage[k] = true;
        first[k] = skipTaken || target ? std::max<int64_t>(s0, film.samples(x, y)) : s0;
        end[k] = target ? int((*target)[size_t(y) * size_t(camera.width()) + size_t(x)]) : s1;
        if (target) last = std::max(last, end[k] - first[k]);
        else begin = std::min(begin, first[k]);
      }
      for (int step = begin; step < last; ++step) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return false;
        Ray ray[B * B];
        Sampler sampler[B * B];
        SampleInfo info[B * B];
        Color L[B * B];
        bool wanted[B * B] = {}, traced[B * B] = {};
        for (int k = 0; k < count; ++k) {
          if (!inImage[k]) continue;
          const int s = target ? first[k] + step : step;
          wanted[k] = s >= first[k] && s < end[k];
          traced[k] = target ? wanted[k] : true;
          if (!traced[k]) continue;
          const int x = bx + k % B, y = by + k / B;
          const uint64_t pixel = uint64_t(y) * uint64_t(camera.width()) + uint64_t(x);
          sampler[k] = Sampler::make(mode, seed, pixel, uint64_t(s));
          const Vec2 jitter = cameraJitter(sampler[k], mode, seed, jitterSeed, pixel, uint64_t(s));
          ray[k] = camera.generateRay(float(x) + jitter.x, float(y) + jitter.y);
        }
        integrator.LiBlock(ray, traced, wanted, count, sampler, info, L);
        for (int k = 0; k < count; ++k) {
          if (!wanted[k]) continue;
          rays += info[k].rays;
          ++samples;
          if (!isFinite(L[k])) {
            ++nonFinite;
            L[k] = Color(0.0f);
          }
          film.add(bx + k % B, by + k / B, L[k], info[k].albedo, info[k].normal);
        }
      }
    }
  return true;
}

}  // namespace

RenderStats render(const Integrator& integrator, const Camera& camera, Film& film, const RenderOptions& options) {
  if (film.width() != camera.width() || film.height() != camera.height())
    throw std::invalid_argument("render: film and camera sizes differ");
  // The render loop by how the integrator renders: splatting integrators have their own; per-pass
  // ones take the sampling loop one sample index at a time, each after their beginPass().
  if (integrator.kind() == IntegratorKind::Splatting)
    return renderSplatting(static_cast<const SplattingIntegrator&>(integrator), camera, film, options);
  const PassIntegrator* perPass = integrator.kind() == IntegratorKind::PerPass
                                      ? static_cast<const PassIntegrator*>(&integrator)
                                      : nullptr;
  Comm& comm = options.comm ? *options.comm : serialComm();
  // This rank's tiles (dealt round-robin over the ranks; all of them with one rank).
  // Tiles of a multiple of 4 pixels, so that renderTile's 4 × 4 blocks lie on the image's grid of blocks
  // whatever the tile size: a block's camera rays, traced together, never depend on it.
  std::vector<Tile> tiles = makeTiles(camera.width(), camera.height(), (std::max(1, options.tileSize) + 3) / 4 * 4);
  std::vector<PixelRect> mine;
  std::vector<uint64_t> tileIndex;  // of mine among all tiles
  for (size_t t = 0, kept = 0; t < tiles.size(); ++t)
    if (comm.mine(t)) {
      tiles[kept++] = tiles[t], mine.push_back({tiles[t].x0, tiles[t].y0, tiles[t].x1, tiles[t].y1});
      tileIndex.push_back(t);
    }
  tiles.resize(mine.size());
  const uint64_t pixels = uint64_t(camera.width()) * uint64_t(camera.height());
  std::atomic<uint64_t> rays{0}, nonFinite{0}, cameraSamples{0};
  std::atomic<bool> cancelled{false};
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  // One pass over all tiles for samples [s0, s1).
  auto tilePass = [&](int s0, int s1, Progress& progress, const std::vector<uint32_t>* target = nullptr) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
        enableFlushToZero();
        for (size_t t = r.begin(); t < r.end(); ++t) {
          if (options.cancel && options.cancel->load(std::memory_order_relaxed)) {
            cancelled = true;
            continue;
          }
          uint64_t tileRays = 0, tileBad = 0, tileSamples = 0;
          if (!renderTile(integrator, camera, film, tiles[t], s0, s1, options.seed,
                          options.jitterSeed.value_or(options.seed), options.sampler, options.skipTaken,
                          options.cancel, target, tileRays, tileBad, tileSamples))
            cancelled = true;
          rays += tileRays;
          nonFinite += tileBad;
          cameraSamples += tileSamples;
          const Tile& tl = tiles[t];
          progress.advance(target ? tileSamples : uint64_t(tl.x1 - tl.x0) * uint64_t(tl.y1 - tl.y0) * uint64_t(s1 - s0));
        }
      });
    });
  };
  // Integrators with a per-pass state: one sample index at a time, each after its beginPass().
  auto pass = [&](int s0, int s1, Progress& progress) {
    if (!perPass) return tilePass(s0, s1, progress);
    for (int s = s0; s < s1; ++s) {
      // Every rank runs each beginPass (the integrator's exchanges are collective), so all stop together.
      if (comm.any(cancelled)) {
        cancelled = true;
        break;
      }
      arena.execute([&] { perPass->beginPass(s, options.seed); });
      if (options.cancel && options.cancel->load()) cancelled = true;  // beginPass may have stopped early
      if (comm.any(cancelled)) {
        cancelled = true;
        break;
      }
      tilePass(s, s + 1, progress);
    }
  };
  // Rank 0's film receives the other ranks' pixels.
  auto collect = [&] { collectFilm(comm, film, mine); };

  RenderStats stats;
  const bool adaptive = options.adaptive && integrator.kind() == IntegratorKind::Sampling && !options.afterPass;
  if (adaptive) {
    // Uniform passes, then rounds whose targets follow the pixels' error (adaptive_sampling.h); without a time
    // limit until the samples' mean reaches options.spp.
    const bool timed = options.timeLimit > 0;
    const double image = double(pixels), budget = timed ? 0.0 : image * double(std::max(1, options.spp));
    Progress progress = timed ? Progress::timed("render", options.timeLimit, options.quiet)
                              : Progress("render", uint64_t(budget), options.quiet);
    const int base = timed ? kAdaptiveBase : std::min(std::max(1, options.spp), kAdaptiveBase);
    int s = options.firstSample, round = 0;
    while (true) {
      if (s < options.firstSample + base) {
        tilePass(s, s + 1, progress);
        ++s;
      } else {
        double extras = kAdaptiveExtras * image;
        if (!timed) {
          const double left = budget - double(comm.sum(cameraSamples));
          if (left < image) break;
          extras = std::min(extras, left - image);
        }
        const std::vector<uint32_t> target =
            adaptiveTargets(film, mine, tileIndex, comm, options.seed, round++, extras);
        tilePass(0, 0, progress, &target);
      }
      if (comm.any(cancelled)) {
        cancelled = true;
        break;
      }
      if (timed && comm.any(comm.root() && seconds() >= options.timeLimit)) break;
    }
    progress.finish();
  } else if (options.timeLimit > 0) {
    Progress progress = Progress::timed("render", options.timeLimit, options.quiet);
    int s = options.firstSample;
    while (true) {
      pass(s, s + 1, progress);
      if (comm.any(cancelled)) {  // rank 0's partial pass is what one process leaves
        cancelled = true;
        break;
      }
      ++s;
      if (options.afterPass) collect(), options.afterPass(s);
      if (comm.any(comm.root() && seconds() >= options.timeLimit)) break;  // rank 0's clock decides
    }
    progress.finish();
    stats.spp = s - options.firstSample;
  } else {
    const int spp = std::max(1, options.spp);
    Progress progress("render", pixels * uint64_t(spp), options.quiet);
    if (options.afterPass) {
      for (int s = options.firstSample; s < options.firstSample + spp; ++s) {
        pass(s, s + 1, progress);
        if (comm.any(cancelled)) {
          cancelled = true;
          break;
        }
        collect();
        options.afterPass(s + 1);
      }
    } else {
      pass(options.firstSample, options.firstSample + spp, progress);
    }
    progress.finish();
    stats.spp = spp;
  }
  collect();
  rays = comm.sum(rays), nonFinite = comm.sum(nonFinite);
  stats.seconds = seconds();
  stats.rays = rays;
  stats.nonFinite = nonFinite;
  stats.cancelled = cancelled;
  stats.cameraSamples = pixels * uint64_t(stats.spp);
  if (adaptive) {  // the samples per pixel: their mean
    stats.cameraSamples = comm.sum(cameraSamples);
    stats.spp = int(std::lround(double(stats.cameraSamples) / double(pixels)));
  }
  return stats;
}

}  // namespace firstshot
