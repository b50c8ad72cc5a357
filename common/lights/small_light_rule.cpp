#include "common/lights/small_light_rule.h"

#include "common/lights/form_factors.h"

namespace firstshot {

double lightSolidAngleFromCentre(const SceneDesc& scene, const LightDesc& light) {
  if (light.type != LightType::Area) return 0.0;
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  const Vec3d centre = 0.5 * (lo + hi);
  const ShapeDesc& s = scene.shapes[light.shape];
  double omega = 0;
  for (const Face& f : s.faces) {
    std::vector<Vec3d> poly;
    for (int i = 0; i < f.count; ++i) poly.push_back(s.vertices[f.v[i]]);
    omega += analytic::solidAnglePolygon(centre, poly);
  }
  return omega;
}

bool isSmallLight(const SceneDesc& scene, const LightDesc& light, double maxSolidAngle) {
  if (light.small == SmallOverride::Small) return true;
  if (light.small == SmallOverride::Large) return false;
  return lightSolidAngleFromCentre(scene, light) <= maxSolidAngle;
}

std::vector<uint32_t> smallLights(const SceneDesc& scene, double maxSolidAngle) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < scene.lights.size(); ++i)
    if (isSmallLight(scene, scene.lights[i], maxSolidAngle)) out.push_back(i);
  return out;
}

}  // namespace firstshot
