// Light tracing: light subpaths connected to the pinhole camera.
#include "render/integrators/light/light_tracer.h"

#include <cmath>

#include "render/direct_light.h"

namespace fs {

void LightTracingIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  emission_ = EmissionSampler(scene.lights(), scene.desc());
  fallback_.preprocess(scene);
}

Color LightTracingIntegrator::Li(const Ray& ray, Sampler& sampler, SampleInfo* info) const {
  Hit hit;
  if (info) info->rays = 1;
  if (!scene_->intersect(ray, hit)) return Color(0.0f);
  const BSDF& bsdf = scene_->bsdf(scene_->material(hit));
  if (bsdf.hasDelta()) {
    const Color L = fallback_.Li(ray, sampler, info);
    if (info) ++info->rays;
    return L;
  }
  if (info) {
    const Vec3 wo = -glm::normalize(ray.d);
    info->albedo = bsdf.albedo();
    info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
  }
  return Color(0.0f);
}

bool LightTracingIntegrator::connect(const LightVertex& v, const Camera& camera, uint32_t& pixel, Color& L,
                                     uint64_t& rays) const {
  if (v.delta) return false;
  CameraConnection c;
  if (!camera.connect(v.hit.p, c)) return false;
  float cosX = glm::dot(v.hit.ng, c.wi);
  if (v.material == kNoId) {  // vertex 0 on an area light: Le towards the camera, front side only
    if (!(cosX > 0.0f)) return false;
    L = v.beta * (cosX * c.importance);
  } else {
    const Frame frame(v.hit.ng);
    const BSDFQuery q(frame.toLocal(v.wi), frame.toLocal(c.wi), TransportMode::Importance);
    const Color f = scene_->bsdf(v.material).eval(q);
    if (!(maxComponent(f) > 0.0f)) return false;
    L = v.beta * f * (std::abs(cosX) * c.importance);
  }
  ++rays;
  if (scene_->occluded(shadowRay(v.hit, c.wi, c.distance))) return false;
  pixel = uint32_t(c.raster.y) * uint32_t(camera.width()) + uint32_t(c.raster.x);
  return true;
}

void LightTracingIntegrator::splatParticles(const Camera& camera, uint64_t seed, uint64_t pass, uint64_t begin,
                                            uint64_t end, std::vector<Splat>& out, uint64_t& rays) const {
  const float invN = 1.0f / float(particlesPerPass(camera));
  const LightPathOptions po = pathOptions();
  std::vector<LightVertex> path;
  for (uint64_t i = begin; i < end; ++i) {
    Sampler sampler(seed, i, pass, kParticleStream);
    if (!traceLightPath(*scene_, emission_, po, sampler, path, rays)) continue;
    for (const LightVertex& v : path) {
      Splat s;
      if (!connect(v, camera, s.pixel, s.L, rays)) continue;
      s.L *= invN;
      out.push_back(s);  // the renderer counts and drops non-finite ones
    }
  }
}

}  // namespace fs
