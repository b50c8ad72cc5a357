// --integrator auto's pilot: the part of a seeded preprocessing's noise (the irradiance cache's records') that more
// passes leave, its records' own noise in it, and how its passes fall with the render's sampler.
#include "render/loop/pilot_records.h"

#include <algorithm>
#include <cmath>

#include "render/loop/pilot_image.h"

namespace firstshot {

namespace {

/// A seeded preprocessing's passes' rate: its fill's picture over the first fill's records, two seeds, the render's
/// sampler, at kRateFew and kRateMany passes; the noise falls as passes^−rate, rate within [0.5, 1]. The cache's
/// passes (a smooth lookup and the direct light, few dimensions) gain from the render's stratified samples far more
/// than the pilot's two independent passes show: in Bitterli's box the render's passes left 0.0015 of its 0.0103 where
/// the pilot projected 0.0074 at passes^−0.5, and it took 512 rays per record where 1024 reached 0.0073 (1.99× the
/// efficiency); measured rates elsewhere 0.65–0.97 (docs/measurements.md).
constexpr int kRateFew = 4, kRateMany = 32;
constexpr double kMinPassRate = 0.5, kMaxPassRate = 1.0;

}  // namespace

void measureRecords(Integrator& first, Integrator& second, const std::vector<double>& a, const PilotPicture& p,
                    PilotFigure& f) {
  const CameraDesc& desc = p.desc;
  const CameraDesc& fillDesc = p.fillDesc;
  const RenderScene& scene = p.scene;
  const std::vector<uint8_t>& skip = p.skip;
  const uint64_t seed = p.seed;
  const SamplerMode passSampler = p.passSampler, sampler = p.sampler;
  const int threads = p.threads;
  const Camera camera(desc);
  // The second fill's records under the first image's passes: the same samples at the same positions, only the
  // records differ.
  PilotImage third(second, desc);
  third.renderTo(f.spp, camera, seed, seed, passSampler, threads);
  const std::vector<double> c3 = third.image();
  // Where one fill's records miss a sample and the other's do not, the sample's path (pass noise, which the
  // render's passes, over denser records, average away) differs from a record's value, often by far more
  // than the records differ: the pixels where either fill's picture changes as those paths alone are redrawn
  // are left out of the records' part.
  std::vector<uint8_t> leftOut = skip;
  for (Integrator* fill : {&first, &second}) {
    fill->keyMissPaths(kPilotMissSalt + 1);
    PilotImage redrawn(*fill, desc);
    redrawn.renderTo(f.spp, camera, seed, seed, passSampler, threads);
    const std::vector<double> r = redrawn.image(), &was = fill == &second ? c3 : a;
    for (size_t i = 0; i < r.size(); ++i)
      if (r[i] != was[i]) leftOut[i / 3] = 1;
    fill->keyMissPaths(kPilotMissSalt);
    f.pilotRays += redrawn.rays - redrawn.preprocessing;
  }
  double kept = 0.0, all = 0.0;
  for (size_t i = 0; i < skip.size(); ++i) kept += !leftOut[i], all += !skip[i];
  f.missShare = all > 0.0 ? 1.0 - kept / all : 0.0;
  const double frozen = pilotNoise(a, c3, kept > 0.0 ? &leftOut : &skip);
  // How the render's stratified passes converge over the same records (f.passRate).
  {
    const Camera fillCamera(fillDesc);
    const std::vector<uint8_t> fillSkip = pixelsSeenAsTheyAre(scene, fillDesc);
    PilotImage one(first, fillDesc), two(first, fillDesc);
    double few = 0.0;
    for (const int passes : {kRateFew, kRateMany}) {
      one.renderTo(passes, fillCamera, seed, seed, sampler, threads);
      two.renderTo(passes, fillCamera, seed + 1, seed, sampler, threads);
      const double noise = pilotNoise(one.image(), two.image(), &fillSkip);
      if (passes == kRateFew) {
        few = noise;
      } else if (few > 0.0 && noise > 0.0) {
        f.passRate = std::clamp(std::log(few / noise) / std::log(double(kRateMany) / double(kRateFew)),
                                kMinPassRate, kMaxPassRate);
      }
    }
    f.pilotRays += one.rays + two.rays - one.preprocessing - two.preprocessing;
  }
  // Of that, the records' own noise: the first image's passes again over its records, each value drawn once
  // more from its own error. Their difference is one copy of that noise (the third image's holds two).
  first.perturbPreprocessing(seed + 2);
  PilotImage fourth(first, desc);
  fourth.renderTo(f.spp, camera, seed, seed, passSampler, threads);
  // The frozen part at least that.
  f.recordNoise = std::sqrt(2.0) * pilotNoise(a, fourth.image(), &skip);
  f.frozen = std::min(f.noise, std::max(frozen, f.recordNoise));
  f.recordNoise = std::min(f.recordNoise, f.frozen);
  f.pilotRays += 2.0 * (f.rays - f.preprocessRays);
}

}  // namespace firstshot
