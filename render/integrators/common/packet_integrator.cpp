// Sampling integrators whose camera rays a block traces as one Embree packet.
#include "render/integrators/common/packet_integrator.h"

#include "render/scene/embree_scene.h"

namespace firstshot {

Color PacketIntegrator::Li(const Ray& ray, Sampler& sampler, SampleInfo* info) const {
  uint64_t rays = 0;
  const Color L = LiFrom(ray, nullptr, sampler, info, rays);
  if (info) info->rays = rays;
  return L;
}

void PacketIntegrator::LiBlock(const Ray* rays, const bool* traced, const bool* wanted, int count, Sampler* samplers,
                               SampleInfo* infos, Color* L) const {
  Hit hits[16];
  bool found[16];
  scene_->embree().intersect16(rays, traced, count, hits, found);
  for (int k = 0; k < count; ++k) {
    if (!wanted[k]) continue;
    uint64_t n = 1;  // the camera ray
    L[k] = found[k] ? LiFrom(rays[k], &hits[k], samplers[k], &infos[k], n) : background(rays[k].d);
    infos[k].rays = n;
  }
}

Color PacketIntegrator::background(const Vec3& dir) const {
  return scene_->lights().background(glm::normalize(dir));
}

}  // namespace firstshot
