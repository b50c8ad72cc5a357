// Path tracing: each camera ray's path walk.
#include "render/integrators/path/integrator.h"

#include "render/scene/embree_scene.h"

namespace fs {

void PathIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  lighting_.build(scene);
  walk_.build(scene, lighting_, options_);
}

Color PathIntegrator::Li(const Ray& cameraRay, Sampler& sampler, SampleInfo* info) const {
  uint64_t rays = 0;
  const Color L = walk_.trace(cameraRay, Color(1.0f), 0, PathVertex(), true, sampler, rays, info);
  if (info) info->rays = rays;
  return L;
}

void PathIntegrator::LiBlock(const Ray* rays, const bool* traced, const bool* wanted, int count, Sampler* samplers,
                             SampleInfo* infos, Color* L) const {
  Hit hits[16];
  bool found[16];
  scene_->embree().intersect16(rays, traced, count, hits, found);
  for (int k = 0; k < count; ++k) {
    if (!wanted[k]) continue;
    uint64_t n = 1;  // the camera ray
    L[k] = found[k] ? walk_.trace(rays[k], Color(1.0f), 0, PathVertex(), true, samplers[k], n, &infos[k], &hits[k])
                    : Color(0.0f);
    infos[k].rays = n;
  }
}

}  // namespace fs
