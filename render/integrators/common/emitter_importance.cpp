// Light tracing's emitters chosen by what the camera sees of their light (emitter_importance.h).
#include "render/integrators/common/emitter_importance.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "render/integrators/common/camera_splat.h"

namespace firstshot {

namespace {

constexpr uint64_t kImportanceChunk = 1024;
constexpr uint64_t kImportanceStream = 0x4549;  // "EI"
constexpr uint64_t kImportanceSeed = 0x456d4963;

}  // namespace

double cameraSplatMoment(const RenderScene& scene, const std::vector<LightVertex>& path, size_t first,
                         const Camera& camera, bool panes, uint64_t& rays, const std::function<bool(size_t)>& skip) {
  double sum = 0;
  for (size_t k = first; k < path.size(); ++k) {
    if (skip && skip(k)) continue;
    uint32_t pixel = 0;
    Color L(0.0f);
    if (!connectToCamera(scene, path[k], camera, pixel, L, rays, panes)) continue;
    const double v = (double(L.x) + L.y + L.z) / 3.0;
    sum += v * v;
  }
  return sum;
}

EmitterImportance measureEmitterImportance(const RenderScene& scene, const EmissionSampler& emission,
                                           const LightPathOptions& walk, bool luminaires, const PathSplatMoment& splat,
                                           uint64_t& rays) {
  EmitterImportance out;
  const size_t emitters = emission.emitterCount();
  if (emitters == 0 || !(emission.totalPower() > 0)) return out;
  // Groups: every light alone, but a luminaire's lights with its exit patches, and the patch sides together.
  const LuminaireBoxes& boxes = scene.luminaires();
  const size_t lights = emission.lightCount(), lumCount = boxes.empty() ? 0 : boxes.items().size();
  const size_t patchGroup = lights, firstLuminaire = lights + 1, groupCount = lights + 1 + lumCount;
  std::vector<uint32_t> group(emitters);
  for (uint32_t e = 0; e < emitters; ++e) {
    if (emission.isPatch(e)) group[e] = uint32_t(patchGroup);
    else if (emission.isExit(e)) group[e] = uint32_t(firstLuminaire + boxes.exitLuminaire(e - emission.exitBegin()));
    else if (const int l = luminaires && lumCount > 0 ? boxes.ofLight(e) : -1; l >= 0)
      group[e] = uint32_t(firstLuminaire + size_t(l));
    else group[e] = e;
  }
  out.groups.assign(groupCount, EmitterGroupMoment());
  for (uint32_t e = 0; e < emitters; ++e) out.groups[group[e]].choice += emission.pdfChoice(e);

  const uint64_t particles = importanceParticles(size_t(std::count_if(
      out.groups.begin(), out.groups.end(), [](const EmitterGroupMoment& g) { return g.choice > 0; })));
  const uint64_t chunks = particles / kImportanceChunk;
  // Per chunk and group: particles, Σ splat moments, rays.
  std::vector<double> sums(3 * groupCount * chunks, 0.0);
  tbb::parallel_for(uint64_t(0), chunks, [&](uint64_t c) {
    std::vector<LightVertex> path;
    double* mine = &sums[3 * groupCount * c];
    for (uint64_t i = c * kImportanceChunk; i < (c + 1) * kImportanceChunk; ++i) {
      Sampler sampler(kImportanceSeed, i, 0, kImportanceStream);
      uint64_t r = 0;
      const bool traced = traceLightPath(scene, emission, walk, sampler, path, r, i, particles);
      if (!traced || path.empty()) continue;  // no emitter known: its rays count nowhere (a few, at most)
      const size_t g = group[path[0].light];
      const double m = splat(path, r);
      mine[3 * g] += 1, mine[3 * g + 1] += m, mine[3 * g + 2] += double(r);
    }
  });
  double totalRays = 0, totalParticles = 0;
  for (uint64_t c = 0; c < chunks; ++c)
    for (size_t g = 0; g < groupCount; ++g) {
      const double* s = &sums[3 * (groupCount * c + g)];
      out.groups[g].particles += s[0], out.groups[g].moment += s[1], out.groups[g].rays += s[2];
      totalRays += s[2], totalParticles += s[0];
    }
  rays += uint64_t(totalRays);
  const double meanRays = totalParticles > 0 ? totalRays / totalParticles : 1.0;
  double norm = 0, before = 0, after = 0, cost = 0;
  for (EmitterGroupMoment& g : out.groups) {
    g.moment = g.choice * g.moment / double(particles);
    // A group's cost from its own particles where it has a few hundred, else the run's mean.
    g.rays = g.particles >= 256 ? std::max(1.0, g.rays / g.particles) : meanRays;
    norm += std::sqrt(g.moment / g.rays);
  }
  if (!(norm > 0)) {
    out.groups.clear();
    return out;
  }
  for (EmitterGroupMoment& g : out.groups) {
    g.newChoice = (1.0 - kDefensiveShare) * std::sqrt(g.moment / g.rays) / norm + kDefensiveShare * g.choice;
    if (g.choice > 0) before += g.moment / g.choice, cost += g.choice * g.rays;
  }
  double newCost = 0;
  for (const EmitterGroupMoment& g : out.groups)
    if (g.newChoice > 0 && g.choice > 0) after += g.moment / g.newChoice, newCost += g.newChoice * g.rays;
  out.gain = after > 0 && newCost > 0 ? before * cost / (after * newCost) : 1.0;
  out.factor.assign(emitters, 1.0);
  for (uint32_t e = 0; e < emitters; ++e) {
    const EmitterGroupMoment& g = out.groups[group[e]];
    out.factor[e] = g.choice > 0 ? g.newChoice / g.choice : 1.0;
  }
  return out;
}

}  // namespace firstshot
