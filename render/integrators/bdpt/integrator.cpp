// Bidirectional path tracing: both subpaths, every strategy, MIS, splatting.
#include "render/integrators/bdpt/integrator.h"

#include <algorithm>

#include "render/integrators/bdpt/mis.h"
#include "render/integrators/bdpt/strategies.h"
#include "render/integrators/bdpt/subpaths.h"
#include "render/integrators/common/camera_splat.h"

namespace fs {

Color BdptIntegrator::Li(const Ray& ray, Sampler&, SampleInfo* info) const {
  if (!info) return Color(0.0f);
  info->rays = 1;
  Hit hit;
  if (!scene_->intersect(ray, hit)) return Color(0.0f);
  const Vec3 wo = -glm::normalize(ray.d);
  info->albedo = scene_->bsdfAt(hit).albedo();
  info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
  return Color(0.0f);
}

void BdptIntegrator::splatParticles(const Camera& camera, uint64_t seed, SamplerMode mode, uint64_t pass,
                                    uint64_t begin, uint64_t end, std::vector<Splat>& out, uint64_t& rays) const {
  const BdptDensities densities(*scene_, emission(), camera);
  Workspace ws;
  for (uint64_t i = begin; i < end; ++i) {
    Sampler sampler = Sampler::make(mode, seed, i, pass, kStream);
    sample(densities, uint32_t(i), sampler, ws, out, rays);
  }
}

void BdptIntegrator::sample(const BdptDensities& densities, uint32_t pixel, Sampler& sampler, Workspace& ws,
                            std::vector<Splat>& out, uint64_t& rays) const {
  const Camera& camera = densities.camera();
  const int maxDepth = options_.maxDepth;
  const Vec2 jitter = sampler.next2D();
  const Ray ray = camera.generateRay(float(pixel % uint32_t(camera.width())) + jitter.x,
                                     float(pixel / uint32_t(camera.width())) + jitter.y);
  traceCameraPath(densities, ray, maxDepth + 1, options_.rrDepth, sampler, ws.camera, rays);
  const LightPathOptions walk{maxDepth, options_.rrDepth, /*sqrtSurvival=*/false};
  if (!traceLightPath(*scene_, emission(), walk, sampler, ws.lightRaw, rays)) ws.lightRaw.clear();
  toBdptLightPath(densities, ws.lightRaw, ws.light);
  const int nt = int(ws.camera.size()), ns = int(ws.light.size());
  const std::span<const SubpathVertex> cameraPath(ws.camera), lightPath(ws.light);
  // x_m, the first non-delta camera vertex: in table mode, lit patches emit only after it.
  size_t m = 1;
  while (m < ws.camera.size() && ws.camera[m].delta) ++m;

  // A path that ends on a lit patch (table mode) has one bounce more than s + t − 2: the patch's.
  const EmissionSampler& em = emission();
  const int lightExtra = ns > 0 && em.isPatch(ws.light[0].light) ? 1 : 0;

  // t ≥ 2: this pixel's sample.
  Color L(0.0f);
  for (int t = 2; t <= nt; ++t) {
    const SubpathVertex& pt = ws.camera[size_t(t - 1)];
    for (int s = 0; s <= std::max(ns, 1) && s + t - 2 <= maxDepth; ++s) {
      Color c(0.0f);
      if (s == 0) {
        if (t - 2 + (pt.hit.onPatch() ? 1 : 0) > maxDepth) continue;  // a lit patch's emission
        c = connectEmission(densities, pt, shooting_.tableMode() && size_t(t - 1) > m);
        if (maxComponent(c) > 0.0f) c *= misWeight(densities, lightPath, cameraPath, 0, t);
      } else if (s == 1) {
        SubpathVertex sampled;
        c = connectLightSample(densities, pt, sampler, sampled, rays);
        if (t - 1 + (em.isPatch(sampled.light) ? 1 : 0) > maxDepth) c = Color(0.0f);
        if (maxComponent(c) > 0.0f)
          c *= misWeight(densities, std::span<const SubpathVertex>(&sampled, 1), cameraPath, 1, t);
      } else if (s + t - 2 + lightExtra > maxDepth) {
        continue;
      } else {
        c = connectVertices(densities, ws.light[size_t(s - 1)], pt, rays);
        if (maxComponent(c) > 0.0f) c *= misWeight(densities, lightPath, cameraPath, s, t);
      }
      L += c;
    }
  }
  // x_m's direct light is a bounce at x_m (camera vertex m is the path tracer's vertex m − 1): only
  // while m ≤ D; past it the small lights count only where the delta chain meets them. So is that of
  // a polished vertex after x_m (the table's patch sum does not hold it).
  if (shooting_.tableMode())
    L += shooting_.smallLights().estimate(cameraPath, int(m) <= maxDepth ? m : cameraPath.size(), sampler, rays,
                                          size_t(std::max(maxDepth, 0)));
  out.push_back(Splat{pixel, L});

  // t = 1: light vertices s − 1 ≥ 1 joined to the pinhole, over the N light subpaths of the pass.
  const float invN = 1.0f / float(particlesPerPass(camera));
  for (int s = 2; s <= ns && s - 1 + lightExtra <= maxDepth; ++s) {
    Splat splat;
    if (!connectToCamera(*scene_, ws.lightRaw[size_t(s - 1)], camera, splat.pixel, splat.L, rays, true)) continue;
    splat.L *= misWeight(densities, lightPath, cameraPath.first(1), s, 1) * invN;
    out.push_back(splat);
  }
}

}  // namespace fs
