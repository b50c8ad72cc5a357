// Whether light tracing and BDPT split a luminaire's light at its box (luminaire_split.h).
#include "render/integrators/common/luminaire_split.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "render/integrators/common/camera_splat.h"
#include "render/integrators/common/light_path.h"
#include "render/scene/camera.h"

namespace firstshot {

namespace {

constexpr uint64_t kChunk = 1024;
constexpr uint64_t kStream = 0x5350;  // "SP"
constexpr uint64_t kSeed = 0x4c756d53;

double gray(const Color& c) { return (double(c.x) + c.y + c.z) / 3.0; }

}  // namespace

std::vector<LuminaireSplit> measureLuminaireSplits(const RenderScene& scene, const EmissionSampler& plain, int maxDepth,
                                                   uint64_t& rays) {
  const LuminaireBoxes& boxes = scene.luminaires();
  const size_t n = boxes.empty() ? 0 : boxes.items().size();
  std::vector<LuminaireSplit> out(n);
  if (n == 0 || !(plain.totalPower() > 0)) return out;
  const Camera camera(scene.desc().camera);
  const uint64_t chunks = kSplitParticles / kChunk;
  // Per chunk and luminaire: Σ over its particles of Σ over their splats of the splat's value², inner and exit part.
  std::vector<double> sums(2 * n * chunks, 0.0);
  std::vector<uint64_t> chunkRays(chunks, 0);
  LightPathOptions walk{maxDepth, 3};
  tbb::parallel_for(uint64_t(0), chunks, [&](uint64_t c) {
    std::vector<LightVertex> path;
    uint64_t r = 0;
    for (uint64_t i = c * kChunk; i < (c + 1) * kChunk; ++i) {
      Sampler sampler(kSeed, i, 0, kStream);
      if (!traceLightPath(scene, plain, walk, sampler, path, r, i, kSplitParticles) || path.empty()) continue;
      const uint32_t l = path[0].light;
      const int lum = l < plain.lightCount() ? boxes.ofLight(l) : -1;
      if (lum < 0) continue;
      const Luminaire* box = &boxes.items()[size_t(lum)];
      bool scattered = false, exitPart = false;  // as traceLightPath splits a luminaire's path at its box
      for (size_t k = 0; k < path.size(); ++k) {
        if (k > 0 && box && !box->contains(path[k].hit.p)) {
          exitPart = scattered;
          box = nullptr;
        }
        if (k > 0 && box) scattered = scattered || !path[k].delta;
        uint32_t pixel = 0;
        Color L(0.0f);
        if (!connectToCamera(scene, path[k], camera, pixel, L, r, true)) continue;
        const double v = gray(L);
        sums[2 * (n * c + size_t(lum)) + (exitPart ? 1 : 0)] += v * v;
      }
    }
    chunkRays[c] = r;
  });
  for (uint64_t c = 0; c < chunks; ++c) {
    rays += chunkRays[c];
    for (size_t i = 0; i < n; ++i) out[i].inner += sums[2 * (n * c + i)], out[i].exit += sums[2 * (n * c + i) + 1];
  }
  for (size_t i = 0; i < n; ++i) {
    LuminaireSplit& s = out[i];
    const Luminaire& lum = boxes.items()[i];
    const double power = gray(lum.power), f = power > 0 ? gray(lum.exitPower) / power : 0.0;
    s.inner /= double(kSplitParticles), s.exit /= double(kSplitParticles);
    const double a = std::sqrt(s.inner), b = std::sqrt(f * s.exit);
    s.split = f > 0 && s.exit > 0 && (a + b) * (a + b) < s.inner + s.exit;
    if (!s.split) continue;
    // x = a/(a + b) of the particles to the lights: their weight x/(1 − x)·f of their power beside the exits' f.
    s.innerShare = std::clamp(f * a / b, EmissionSampler::kMinInnerShare, 1.0);
  }
  return out;
}

EmissionSampler emittersWithExits(const RenderScene& scene, const EmissionSampler& plain, int maxDepth, bool everyOne) {
  EmissionSampler out = plain;
  if (everyOne) {
    out.addExits(scene.luminaires());
    return out;
  }
  // Measured once per scene and emitters (the scene's memo): the pilot's light and BDPT candidates and the render
  // would each measure the same.
  const std::string key = fmt::format("LuminaireSplits/{}/{}/{}/{:a}", maxDepth, plain.lightCount(),
                                      plain.patchSideCount(), plain.totalPower());
  std::shared_ptr<const std::vector<double>> shares = scene.memo().find<std::vector<double>>(key);
  if (!shares) {
    auto made = std::make_shared<std::vector<double>>();
    uint64_t rays = 0;
    for (const LuminaireSplit& s : measureLuminaireSplits(scene, plain, maxDepth, rays))
      made->push_back(s.split ? s.innerShare : 0.0);
    shares = made;
    scene.memo().keep(key, shares);
  }
  out.addExits(scene.luminaires(), *shares);
  return out;
}

}  // namespace firstshot
