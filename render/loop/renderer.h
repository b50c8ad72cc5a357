#pragma once
/// @file renderer.h
/// The render loop: image tiles in parallel (TBB), every pixel sample seeded by
/// (seed, pixel index, sample index), each pixel's samples accumulated in sample order — so the
/// image is bit-identical for any number of threads.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>

#include "common/sampling/rng.h"
#include "common/util/comm.h"
#include "render/integrators/integrator.h"
#include "render/output/film.h"
#include "render/scene/camera.h"

namespace firstshot {

struct RenderOptions {
  int spp = 16;            ///< samples per pixel (ignored when timeLimit > 0)
  double timeLimit = 0;    ///< seconds; > 0: whole passes of 1 spp until the time is up (at least one)
  /// Adaptive sampling (render/loop/adaptive_sampling.h; not with afterPass, nor with a PerPass integrator):
  /// after kAdaptiveBase uniform passes, rounds that give each pixel one sample and share as many again out by
  /// the pixels' estimated error, until the time limit or until the samples' mean reaches spp (RenderStats::spp
  /// is then that mean). A splatting integrator's passes stay passes, and what is shared out are more
  /// estimates of each pixel's camera side (SplattingIntegrator's Li: light tracing's path-traced pixels at
  /// mirrors and glass) within its pass; BDPT, whose camera samples are all particles, renders as without.
  bool adaptive = false;
  uint64_t seed = 1;
  /// How the camera samples' numbers are drawn (common/sampling/rng.h; --sampler): independent hashes, or
  /// per pixel stratified Sobol' points over the sample index. The image stays a function of
  /// (seed, pixel, sample index) in both.
  SamplerMode sampler = SamplerMode::Independent;
  /// The seed of the camera samples' positions in their pixels, where it is not `seed` (cameraJitter,
  /// common/sampling/rng.h): the integrator pilot renders its two images of two seeds at the same positions.
  std::optional<uint64_t> jitterSeed;
  int threads = 0;         ///< worker threads; 0 = one per core
  int tileSize = 16;       ///< pixels along a tile's side
  bool quiet = true;       ///< no progress bar
  /// Index of the first sample taken per pixel: render() takes samples [firstSample, firstSample + spp).
  /// Progressive rendering (the preview) renders pass k as {firstSample = k, spp = 1}; the passes
  /// 0..n-1 then give the same film, bit for bit, as one render with spp = n.
  int firstSample = 0;
  /// Pass @p k alone: one sample per pixel, sample index @p k, seed @p seed (every other field its default).
  static RenderOptions pass(int k, uint64_t seed) {
    RenderOptions ro;
    ro.spp = 1;
    ro.firstSample = k;
    ro.seed = seed;
    return ro;
  }
  /// If set, checked before each tile and each sample: once true, the render stops, every pixel
  /// holding its first samples in order (a partial pass), and RenderStats::cancelled is set.
  /// Splatting integrators check it per particle chunk and leave the film at a pass boundary.
  const std::atomic<bool>* cancel = nullptr;
  /// Resuming a film restored from a checkpoint (render/loop/checkpoint.h): pixel (x, y) takes only the
  /// sample indices it does not hold yet (s >= film.samples(x, y)), so a film saved in the middle
  /// of a pass continues exactly. Splatting integrators need every pixel to hold firstSample samples.
  bool skipTaken = false;
  /// If set, called between passes with the number of sample indices done (firstSample + passes
  /// so far); the film then holds whole passes (for checkpoints). The render then goes pass by
  /// pass (one sample index over the whole image at a time), which gives the same image.
  std::function<void(int samplesDone)> afterPass;
  /// The ranks of an MPI run (common/util/comm.h; null: this process alone): each renders the image
  /// tiles dealt to it (splatting integrators: its share of each pass's particles, whose splats are
  /// exchanged), and rank 0's film receives the other ranks' pixels before afterPass and at the
  /// end, so that it is bit-identical for any number of ranks. With a time limit rank 0's clock
  /// decides when to stop. The other ranks' films hold only their own pixels.
  Comm* comm = nullptr;
};

struct RenderStats {
  int spp = 0;                 ///< samples per pixel actually taken
  double seconds = 0;          ///< wall-clock time of the render loop
  uint64_t rays = 0;           ///< rays traced (closest-hit and shadow)
  uint64_t cameraSamples = 0;  ///< camera samples taken
  uint64_t nonFinite = 0;      ///< samples whose estimate was NaN or Inf (recorded as 0)
  bool cancelled = false;      ///< RenderOptions::cancel stopped the render
};

/// Renders into @p film (which must be camera.width() × camera.height()). The integrator must
/// have been preprocessed. With a time limit the image depends on how many passes fit. The loop
/// follows Integrator::kind(): a splatting integrator's is renderSplatting() (render/loop/splat_renderer.h);
/// a per-pass one (PassIntegrator) gets beginPass(s, seed) before the camera samples of each sample index s.
RenderStats render(const Integrator& integrator, const Camera& camera, Film& film, const RenderOptions& options);

}  // namespace firstshot
