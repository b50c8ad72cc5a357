// One of --integrator auto's pilot images in the making (render/loop/integrator_pilot.h): passes of a preprocessed
// integrator over the pilot's picture, and the rays they took.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/sampling/rng.h"
#include "common/util/interrupt.h"
#include "render/integrators/integrator.h"
#include "render/loop/renderer.h"
#include "render/output/film.h"
#include "render/scene/camera.h"

namespace firstshot {

/// One pilot image in the making: passes of 1 spp at sample indices 0, 1, ... of a preprocessed integrator.
struct PilotImage {
  const Integrator& integrator;
  Film film;
  double rays = 0;       ///< traced so far, the integrator's preprocessing included
  double preprocessing = 0;  ///< of those, the preprocessing's
  double firstPass = 0;  ///< rays of its first pass
  int passes = 0;

  PilotImage(const Integrator& i, const CameraDesc& desc)
      : integrator(i), film(desc.width, desc.height), rays(double(i.preprocessRayCount())), preprocessing(rays) {}
  /// Renders passes until @p total are done, their camera samples at the positions in their pixels that seed
  /// @p jitterSeed draws.
  void renderTo(int total, const Camera& camera, uint64_t seed, uint64_t jitterSeed, SamplerMode sampler,
                int threads) {
    for (; passes < total; ++passes) {
      RenderOptions ro = RenderOptions::pass(passes, seed);
      ro.jitterSeed = jitterSeed;
      ro.sampler = sampler;
      ro.threads = threads;
      ro.quiet = true;
      ro.cancel = &interruptFlag();  // SIGINT/SIGTERM stop the pilot too (thrown by runPilot)
      const double r = double(render(integrator, camera, film, ro).rays);
      throwIfInterrupted("no output written (interrupted in the integrator pilot)");
      if (passes == 0) firstPass = r;
      rays += r;
    }
  }
  /// The film's means, interleaved RGB (a non-finite value as 0).
  std::vector<double> image() const {
    std::vector<double> out;
    out.reserve(size_t(film.width()) * size_t(film.height()) * 3);
    for (int y = 0; y < film.height(); ++y)
      for (int x = 0; x < film.width(); ++x) {
        const Vec3d m = film.mean(x, y);
        for (int ch = 0; ch < 3; ++ch) out.push_back(std::isfinite(m[ch]) ? m[ch] : 0.0);
      }
    return out;
  }
};

}  // namespace firstshot
