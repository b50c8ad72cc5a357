// Path tracing: each camera ray's path walk.
#include "render/integrators/path/integrator.h"

namespace firstshot {

void PathIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  lighting_.build(scene);
  walk_.build(scene, lighting_, options_);
}

Color PathIntegrator::LiFrom(const Ray& ray, const Hit* first, Sampler& sampler, SampleInfo* info,
                             uint64_t& rays) const {
  return walk_.trace(ray, Color(1.0f), 0, PathVertex(), true, sampler, rays, info, first);
}

Color PathIntegrator::LiFromSensor(const Ray& ray, const PathVertex& from, Sampler& sampler, SampleInfo* info) const {
  uint64_t rays = 0;
  const Color L = walk_.trace(ray, Color(1.0f), 0, from, false, sampler, rays, info);
  if (info) info->rays = rays;
  return L;
}

}  // namespace firstshot
