// Light tracing: light subpaths connected to the pinhole camera.
#include "render/integrators/light/integrator.h"

#include <algorithm>
#include <cmath>

#include "render/firstshot/patch_emitters.h"
#include "render/integrators/common/camera_splat.h"

namespace firstshot {

void LightTracingIntegrator::preprocess(const RenderScene& scene) {
  ShootingIntegrator::preprocess(scene);
  IntegratorOptions walk = options_;
  walk.luminaires = false;  // the particles leave the luminaires' lights themselves
  fallback_.build(scene, lighting_, walk);
  mirrors_ = false;
  for (size_t m = 0; m < scene.desc().materials.size(); ++m) mirrors_ = mirrors_ || scene.bsdf(uint32_t(m)).hasDelta();
  polished_ = mayBePolished(scene);
  const Camera camera(scene.desc().camera);
  chooseEmitters("light", pathOptions(),
                 [&](const std::vector<LightVertex>& path, uint64_t& rays) { return splatMoment(path, camera, rays); });
  if (!shooting_.tableMode()) return;
  deltaFirst_ = EmissionSampler(scene.lights(), scene.desc(), EmitterSet::ReplacedAreaLights);
  smallAreaLights_ = deltaFirst_.totalPower() > 0;
  deltaParticles_ = smallAreaLights_ && mirrors_;
  if (!polished_) return;
  // Polished surfaces: the first-hit particles leave every replaced light (NEE reaches them all there).
  deltaFirst_ = EmissionSampler(scene.lights(), scene.desc(), EmitterSet::Replaced);
  deltaParticles_ = deltaFirst_.totalPower() > 0;
}

double LightTracingIntegrator::splatMoment(const std::vector<LightVertex>& path, const Camera& camera,
                                           uint64_t& rays) const {
  const EmissionSampler& emission = particleEmitters();
  const uint32_t e = path[0].light;
  // As splatParticles() splats the path: a patch's or exit's vertex 0 not, no vertex that Li() path traces.
  return cameraSplatMoment(*scene_, path, emission.isPatch(e) || emission.isExit(e) ? 1 : 0, camera, false, rays,
                           [&](size_t k) {
                             return polished_ && k > 0 && pathTraced(path[k].hit, scene_->bsdfAt(path[k].hit));
                           });
}

bool LightTracingIntegrator::pathTraced(const Hit& hit, const BSDF& bsdf) const {
  return bsdf.hasDelta() || (polished_ && hit.onPatch() && bsdf.tooSharpForTable());
}

LightPathOptions LightTracingIntegrator::pathOptions() const {
  LightPathOptions o{options_.maxDepth, options_.rrDepth};
  if (luminaires_) o.luminaires = &scene_->luminaires();
  return o;
}

int LightTracingIntegrator::pathsPerPixel(const Camera& camera) const {
  if (options_.lightPathsPerPixel > 0) return options_.lightPathsPerPixel;
  if (mirrors_) return 1;
  const uint64_t pixels = std::max<uint64_t>(1, uint64_t(camera.width()) * uint64_t(camera.height()));
  const int automatic = int(std::clamp<uint64_t>(kAutoPathsPerPass / pixels, 1, kAutoPathsPerPixel));
  return options_.lightPathsCap > 0 ? std::min(automatic, options_.lightPathsCap) : automatic;
}

Color LightTracingIntegrator::Li(const Ray& ray, Sampler& sampler, SampleInfo* info) const {
  Hit hit;
  if (info) info->rays = 1;
  if (!scene_->intersect(ray, hit)) return Color(0.0f);
  const BSDF bsdf = scene_->bsdfAt(hit);
  if (pathTraced(hit, bsdf)) {  // the path tracer's estimate, the first hit traced again (as PathIntegrator::Li)
    uint64_t rays = 0;
    const Color L = fallback_.trace(ray, Color(1.0f), 0, PathVertex(), true, sampler, rays, info);
    if (info) info->rays = rays + 1;
    return L;
  }
  if (info) {
    const Vec3 wo = -glm::normalize(ray.d);
    info->albedo = bsdf.albedo();
    info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
  }
  if (!shooting_.tableMode()) return Color(0.0f);
  uint64_t rays = 0;
  const Color L = smallLightsAt(ray, hit, sampler, rays);
  if (info) info->rays += uint32_t(rays);
  return L;
}

Color LightTracingIntegrator::smallLightsAt(const Ray& ray, const Hit& x, Sampler& sampler, uint64_t& rays) const {
  // The camera subpath: the pinhole, x, and — if a replaced light has a surface to meet — the hit
  // of x's BSDF sample (a small area light seen from x through mirrors and glass comes from the
  // delta-first particles instead).
  thread_local std::vector<SubpathVertex> path;
  path.clear();
  SubpathVertex v;
  v.kind = SubpathVertex::Kind::Camera;
  v.hit.p = ray.o;
  v.beta = Color(1.0f);
  path.push_back(v);
  v = SubpathVertex();
  v.hit = x;
  v.wi = -glm::normalize(ray.d);
  v.beta = Color(1.0f);
  v.material = scene_->material(x);
  path.push_back(v);
  const SmallLightsExact& small = shooting_.smallLights();
  if (options_.maxDepth < 1) return small.estimate(path, path.size(), sampler, rays);  // x's own emission only
  const BSDF bsdf = scene_->bsdfAt(path[1].hit);
  if (smallAreaLights_ && maxComponent(bsdf.albedo()) > 0.0f) {
    const Frame frame = scene_->shadingFrame(x);
    BSDFQuery q(frame.toLocal(path[1].wi));
    const Color weight = bsdf.sample(q, sampler.next2D());
    const Vec3 wi = frame.toWorld(q.wi);
    Hit hit;
    if (q.pdf > 0.0f && maxComponent(weight) > 0.0f && (++rays, scene_->intersect(Ray(x.spawnOrigin(wi), wi), hit))) {
      v = SubpathVertex();
      v.hit = hit;
      v.wi = -wi;
      v.beta = weight;
      v.material = scene_->material(hit);
      v.delta = scene_->bsdf(v.material).hasDelta();
      path.push_back(v);
    }
  }
  return small.estimate(path, 1, sampler, rays);
}

void LightTracingIntegrator::splatPath(const std::vector<LightVertex>& path, size_t first, const Camera& camera,
                                       float invN, std::vector<Splat>& out, uint64_t& rays) const {
  for (size_t k = first; k < path.size(); ++k) {
    Splat s;
    if (polished_ && k > 0 && pathTraced(path[k].hit, scene_->bsdfAt(path[k].hit))) continue;  // Li() has it
    if (!connectToCamera(*scene_, path[k], camera, s.pixel, s.L, rays, false)) continue;  // panes: delta pixels
    s.L *= invN;
    out.push_back(s);  // the renderer counts and drops non-finite ones
  }
}

Sampler LightTracingIntegrator::particleSampler(SamplerMode mode, uint64_t seed, uint64_t particle, uint64_t pass,
                                                uint64_t n, uint64_t stream) {
  if (mode != SamplerMode::Sobol) return Sampler(seed, particle, pass, stream);
  const uint64_t g = pass * n + particle;  // the particle's place in the run's one sequence
  return Sampler::sobol(seed, g >> 32, g, stream);
}

void LightTracingIntegrator::splatParticles(const Camera& camera, uint64_t seed, uint64_t, SamplerMode mode,
                                            uint64_t pass, uint64_t begin, uint64_t end, std::vector<Splat>& out,
                                            uint64_t& rays) const {
  // Particle i of the pass chooses its emitter in stratum i of n (EmissionSampler::sample).
  const uint64_t n = particlesPerPass(camera);
  const float invN = 1.0f / float(n);
  const LightPathOptions po = pathOptions();
  std::vector<LightVertex> path;
  LightPathOptions deltaFirst = po;
  deltaFirst.deltaFirstHitOnly = true;
  deltaFirst.polishedFirstHit = polished_;
  deltaFirst.luminaires = nullptr;  // replaced lights only: none is a luminaire's
  const EmissionSampler& emission = particleEmitters();
  for (uint64_t i = begin; i < end; ++i) {
    Sampler sampler = particleSampler(mode, seed, i, pass, n, kParticleStream);
    if (traceLightPath(*scene_, emission, po, sampler, path, rays, i, n)) {
      // A patch particle (table mode) starts one bounce in (traceLightPath stops it a hit earlier):
      // its vertex 0, the first-shot radiance at the camera's first hit, is the small lights'
      // direct light that Li() takes exactly. An exit particle's vertex 0 lies on a box's face in
      // empty space, which the camera sees through.
      const uint32_t e = path[0].light;
      splatPath(path, emission.isPatch(e) || emission.isExit(e) ? 1 : 0, camera, invN, out, rays);
    }
    // Table mode with mirrors or glass: a small area light's particle whose first hit is a delta
    // surface (no table holds that bounce); with polished surfaces also any small light's particle
    // whose first hit is polished. Its vertex 0 seen by the camera and its vertex 1 come from Li().
    if (!deltaParticles_) continue;
    Sampler second = particleSampler(mode, seed, i, pass, n, kDeltaFirstStream);
    if (traceLightPath(*scene_, deltaFirst_, deltaFirst, second, path, rays, i, n) && path.size() > 2)
      splatPath(path, 2, camera, invN, out, rays);
  }
}

}  // namespace firstshot
