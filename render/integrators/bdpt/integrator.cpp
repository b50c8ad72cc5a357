// Bidirectional path tracing: both subpaths, every strategy, MIS, splatting.
#include "render/integrators/bdpt/integrator.h"

#include <algorithm>

#include "render/integrators/bdpt/luminaire_paths.h"
#include "render/integrators/bdpt/mis.h"
#include "render/integrators/bdpt/strategies.h"
#include "render/integrators/bdpt/subpaths.h"
#include "render/integrators/common/camera_splat.h"

namespace firstshot {

void BdptIntegrator::preprocess(const RenderScene& scene) {
  ShootingIntegrator::preprocess(scene);
  // The light subpaths' emitters chosen by what their vertices joined to the pinhole (strategy t = 1) show.
  const Camera camera(scene.desc().camera);
  LightPathOptions walk{options_.maxDepth, options_.rrDepth, /*sqrtSurvival=*/false};
  if (luminaires_) walk.luminaires = &scene.luminaires();
  chooseEmitters("bdpt", walk, [&](const std::vector<LightVertex>& path, uint64_t& rays) {
    return cameraSplatMoment(scene, path, 1, camera, true, rays);
  });
  deltaParticles_ = false;
  if (!shooting_.tableMode()) return;
  bool mirrors = false;
  for (size_t m = 0; m < scene.desc().materials.size(); ++m) mirrors = mirrors || scene.bsdf(uint32_t(m)).hasDelta();
  deltaFirst_ = EmissionSampler(scene.lights(), scene.desc(), EmitterSet::ReplacedAreaLights);
  deltaParticles_ = mirrors && deltaFirst_.totalPower() > 0;
}

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

void BdptIntegrator::splatParticles(const Camera& camera, uint64_t seed, uint64_t jitterSeed, SamplerMode mode,
                                    uint64_t pass, uint64_t begin, uint64_t end, std::vector<Splat>& out,
                                    uint64_t& rays) const {
  const BdptDensities densities(*scene_, particleEmitters(), camera), deltaDensities(*scene_, deltaFirst_, camera);
  Workspace ws;
  for (uint64_t i = begin; i < end; ++i) {
    Sampler sampler = Sampler::make(mode, seed, i, pass, kStream);
    Sampler deltaSampler = Sampler::make(mode, seed, i, pass, kDeltaFirstStream);
    const Vec2 jitter = cameraJitter(sampler, mode, seed, jitterSeed, i, pass, kStream);
    sample(densities, deltaDensities, uint32_t(i), jitter, sampler, deltaSampler, ws, out, rays);
  }
}

void BdptIntegrator::sample(const BdptDensities& densities, const BdptDensities& deltaDensities, uint32_t pixel,
                            const Vec2& jitter, Sampler& sampler, Sampler& deltaSampler, Workspace& ws,
                            std::vector<Splat>& out, uint64_t& rays) const {
  const Camera& camera = densities.camera();
  const int maxDepth = options_.maxDepth;
  const Ray ray = camera.generateRay(float(pixel % uint32_t(camera.width())) + jitter.x,
                                     float(pixel / uint32_t(camera.width())) + jitter.y);
  traceCameraPath(densities, ray, maxDepth + 1, options_.rrDepth, sampler, ws.camera, rays);
  LightPathOptions walk{maxDepth, options_.rrDepth, /*sqrtSurvival=*/false};
  if (luminaires_) walk.luminaires = &scene_->luminaires();  // a luminaire's light ends where its exit patches take it
  if (!traceLightPath(*scene_, particleEmitters(), walk, sampler, ws.lightRaw, rays)) ws.lightRaw.clear();
  toBdptLightPath(densities, ws.lightRaw, ws.light);
  const int nt = int(ws.camera.size()), ns = int(ws.light.size());
  const std::span<const SubpathVertex> cameraPath(ws.camera), lightPath(ws.light);
  // x_m, the first non-delta camera vertex: in table mode, lit patches emit only after it.
  size_t m = 1;
  while (m < ws.camera.size() && ws.camera[m].delta) ++m;

  // A path that ends on a lit patch (table mode) has one bounce more than s + t − 2: the patch's.
  const EmissionSampler& em = particleEmitters();
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
        if (maxComponent(c) > 0.0f && !pt.hit.onPatch() && !counts(densities.lightOf(pt), {}, 0, cameraPath, t))
          c = Color(0.0f);
        if (maxComponent(c) > 0.0f) c *= misWeight(densities, lightPath, cameraPath, 0, t);
      } else if (s == 1) {
        SubpathVertex sampled;
        c = connectLightSample(densities, pt, sampler, sampled, rays);
        const std::span<const SubpathVertex> light(&sampled, 1);
        if (t - 1 + (em.isPatch(sampled.light) ? 1 : 0) > maxDepth ||
            (maxComponent(c) > 0.0f && !counts(sampled.light, light, 1, cameraPath, t)))
          c = Color(0.0f);
        if (maxComponent(c) > 0.0f)
          c *= misWeight(densities, std::span<const SubpathVertex>(&sampled, 1), cameraPath, 1, t);
      } else if (s + t - 2 + lightExtra > maxDepth) {
        continue;
      } else {
        if (!counts(ws.light[0].light, lightPath, s, cameraPath, t)) continue;
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
                                          size_t(std::max(maxDepth, 0)), deltaParticles_);
  if (deltaParticles_) L += deltaFirstStrategies(deltaDensities, m, deltaSampler, ws, out, rays);
  out.push_back(Splat{pixel, L});

  // t = 1: light vertices s − 1 ≥ 1 joined to the pinhole, over the N light subpaths of the pass.
  const float invN = 1.0f / float(particlesPerPass(camera));
  for (int s = 2; s <= ns && s - 1 + lightExtra <= maxDepth; ++s) {
    if (!counts(ws.light[0].light, lightPath, s, cameraPath.first(1), 1)) continue;
    Splat splat;
    if (!connectToCamera(*scene_, ws.lightRaw[size_t(s - 1)], camera, splat.pixel, splat.L, rays, true)) continue;
    splat.L *= misWeight(densities, lightPath, cameraPath.first(1), s, 1) * invN;
    out.push_back(splat);
  }
}

bool BdptIntegrator::counts(uint32_t l, std::span<const SubpathVertex> light, int s,
                            std::span<const SubpathVertex> camera, int t) const {
  if (!luminaires_ || l >= particleEmitters().lightCount()) return true;
  const int i = scene_->luminaires().ofLight(l);
  return !particleEmitters().splits(i) ||
         !exitPatchesPath(scene_->luminaires().items()[size_t(i)], light, s, camera, t);
}

Color BdptIntegrator::deltaFirstStrategies(const BdptDensities& deltaDensities, size_t m, Sampler& deltaSampler,
                                           Workspace& ws, std::vector<Splat>& out, uint64_t& rays) const {
  const int maxDepth = options_.maxDepth;
  const std::span<const SubpathVertex> cameraPath(ws.camera);
  const int nt = int(ws.camera.size());
  const LightSet& lights = scene_->lights();
  Color L(0.0f);
  // s = 0: the camera subpath meets a small area light right after a mirror or glass beyond x_m (before
  // x_m, and right after x_m, SmallLightsExact weights it: no light subpath makes those paths).
  for (int t = 3; t <= nt; ++t) {
    const SubpathVertex& pt = ws.camera[size_t(t - 1)];
    if (!SmallLightsExact::afterDeltaChain(cameraPath, size_t(t - 1), m) || pt.hit.onPatch() ||
        !lights.emitterLight(pt.hit.emitter).replaced)
      continue;
    const Color Le = lights.emitted(pt.hit, pt.wi);
    if (maxComponent(Le) > 0.0f) L += pt.beta * Le * misWeight(deltaDensities, {}, cameraPath, 0, t);
  }
  // The delta-first light subpath: a small area light's, kept only where its first hit is a mirror or
  // glass (the table holds its other first bounces; traceLightPath stops those at the first hit).
  LightPathOptions walk{maxDepth, options_.rrDepth, /*sqrtSurvival=*/false};
  walk.deltaFirstHitOnly = true;
  if (!traceLightPath(*scene_, deltaFirst_, walk, deltaSampler, ws.deltaRaw, rays) || ws.deltaRaw.size() < 3 ||
      !ws.deltaRaw[1].delta)
    return L;
  toBdptLightPath(deltaDensities, ws.deltaRaw, ws.deltaLight);
  const std::span<const SubpathVertex> lightPath(ws.deltaLight);
  const int ns = int(ws.deltaLight.size());
  // s ≥ 3 (vertex 1 is delta), t ≥ 2: light vertex s − 1 beyond the delta chain (connectVertices refuses
  // delta ends) joined to camera vertex t − 1.
  for (int t = 2; t <= nt; ++t)
    for (int s = 3; s <= ns && s + t - 2 <= maxDepth; ++s) {
      const Color c = connectVertices(deltaDensities, ws.deltaLight[size_t(s - 1)], ws.camera[size_t(t - 1)], rays);
      if (maxComponent(c) > 0.0f) L += c * misWeight(deltaDensities, lightPath, cameraPath, s, t);
    }
  // t = 1: its non-delta vertices joined to the pinhole, over the N light subpaths of the pass.
  const Camera& camera = deltaDensities.camera();
  const float invN = 1.0f / float(particlesPerPass(camera));
  for (int s = 3; s <= ns && s - 1 <= maxDepth; ++s) {
    if (ws.deltaRaw[size_t(s - 1)].delta) continue;
    Splat splat;
    if (!connectToCamera(*scene_, ws.deltaRaw[size_t(s - 1)], camera, splat.pixel, splat.L, rays, true)) continue;
    splat.L *= misWeight(deltaDensities, lightPath, cameraPath.first(1), s, 1) * invN;
    out.push_back(splat);
  }
  return L;
}

}  // namespace firstshot
