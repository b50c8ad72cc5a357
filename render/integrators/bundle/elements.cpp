// The bundle's elements: patches, then emitter triangles; the scene's bounding sphere.
#include "render/integrators/bundle/elements.h"

#include <algorithm>
#include <limits>

namespace firstshot {

void BundleElements::build(const RenderScene& scene) {
  elements_.clear();
  emitterBase_.clear();
  const PatchMesh& mesh = scene.mesh();
  const LightSet& lights = scene.lights();
  Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  auto grow = [&](const Vec3& v) {
    lo = glm::min(lo, Vec3d(v));
    hi = glm::max(hi, Vec3d(v));
  };
  elements_.reserve(mesh.size());
  for (const Patch& p : mesh.patches) {
    elements_.push_back({p.normal, float(p.area), p.material, kNoId});
    for (uint32_t k = 0; k < p.count; ++k) grow(p.v[k]);
  }
  const auto& meshes = lights.emitterMeshes();
  emitterBase_.resize(meshes.size());
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const RenderLight& light = lights.lights()[l];
    if (light.type != LightType::Area) continue;
    const EmitterMesh& m = meshes[light.emitter];
    const uint32_t material = uint32_t(scene.desc().shapes[size_t(light.desc.shape)].material);
    emitterBase_[light.emitter] = size();
    for (uint32_t t = 0; t < m.triangleCount(); ++t) {
      const Vec3 a = m.vertices[m.indices[3 * t]], b = m.vertices[m.indices[3 * t + 1]], c = m.vertices[m.indices[3 * t + 2]];
      const Vec3 cr = glm::cross(b - a, c - a);
      const float len = glm::length(cr);
      elements_.push_back({len > 0.0f ? cr / len : Vec3(0, 0, 1), 0.5f * len, material, uint32_t(l)});
      grow(a), grow(b), grow(c);
    }
  }
  if (elements_.empty()) {
    center_ = Vec3(0.0f), radius_ = 1.0f;
    return;
  }
  center_ = Vec3(0.5 * (lo + hi));
  const double r = 0.5 * glm::length(hi - lo);
  radius_ = float(std::max(r * (1.0 + 1e-4), 1e-6));
}

}  // namespace firstshot
