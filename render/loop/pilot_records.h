// --integrator auto's pilot: what of a seeded preprocessing's noise (the irradiance cache's records') more passes
// leave (render/loop/integrator_pilot.h, PilotFigure::frozen).
#pragma once

#include <cstdint>
#include <vector>

#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "render/integrators/integrator.h"
#include "render/loop/integrator_pilot.h"

namespace firstshot {

/// A seeded preprocessing's pilot images draw the paths of samples its records miss from a stream of their own
/// (Integrator::keyMissPaths) keyed by this, and by this + 1 where measureRecords redraws them.
inline constexpr uint64_t kPilotMissSalt = 0x6d697373;

/// What a seeded preprocessing's pilot images are rendered with.
struct PilotPicture {
  const RenderScene& scene;          ///< the scene as given (pixelsSeenAsTheyAre)
  const CameraDesc& desc;            ///< the pilot picture
  const CameraDesc& fillDesc;        ///< the fills' picture (pilotFillCamera)
  const std::vector<uint8_t>& skip;  ///< the pilot picture's pixels left out (pixelsSeenAsTheyAre)
  uint64_t seed;                     ///< the first image's passes' seed (and their positions in the pixels)
  SamplerMode passSampler;           ///< the pilot images' sampler
  SamplerMode sampler;               ///< the render's
  int threads;
};

/// Into @p f: the frozen part of a seeded preprocessing's noise (frozen, the pixels where a missed sample took a path
/// left out: missShare), its records' own noise (recordNoise), its passes' rate with the render's sampler
/// (passRate), and the rays all that took (pilotRays). @p first and @p second: the two fills (both with their miss
/// paths keyed by kPilotMissSalt; @p first's records are perturbed afterwards), @p a: f.spp passes of @p p's seed over
/// @p first's records; f.noise, f.spp, f.rays and f.preprocessRays measured.
void measureRecords(Integrator& first, Integrator& second, const std::vector<double>& a, const PilotPicture& p,
                    PilotFigure& f);

}  // namespace firstshot
