// NEE, shared by the integrators.
#include "render/direct_light.h"

#include <algorithm>
#include <cmath>

#include "render/firstshot/lighting.h"

namespace fs {

Ray shadowRay(const Hit& hit, const Vec3& wi, float distance) {
  const Vec3 o = hit.spawnOrigin(wi);
  if (std::isinf(distance)) return Ray(o, wi, 0.0f, distance);
  // Aimed from the offset origin at the target itself: a ray shifted parallel to wi by eps along ng
  // meets the light's plane eps·|ng·n_L|/cos θ_L sooner, before tmax where the light is seen at a
  // grazing angle (the limb of an emissive sphere: NEE lost up to 1% of its irradiance there).
  const Vec3 d = hit.p + wi * distance - o;
  const float length = glm::length(d);
  return Ray(o, length > 0.0f ? d / length : wi, 0.0f, length * (1.0f - 1e-4f) - hit.eps);
}

Color estimateDirect(const RenderScene& scene, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                     const DirectLightOptions& options, Sampler& sampler, uint64_t& rays) {
  const LightSet& lights = scene.lights();
  const Color fDiffuse = options.nonDiffuseOnly ? bsdf.diffuseAlbedo() * kInvPiF : Color(0.0f);
  Color sum(0.0f);
  // Light l takes dimensions d0 + 2l and d0 + 2l + 1 (later dimensions do not shift); the lights
  // left out skip theirs without drawing them.
  const uint64_t d0 = sampler.dimension();
  const bool useTable = options.tableVisibility && hit.onPatch();
  TableVisibilityMap::Cursor table;
  if (useTable) table = options.tableVisibility->visibilityCursor(hit.patch);
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const RenderLight& light = lights.lights()[l];
    if (options.skipReplaced && light.replaced) continue;
    if (options.include && !(*options.include)[l]) continue;
    TableVisibility seen = TableVisibility::Unknown;
    if (useTable && light.replaced) {
      seen = table.next(static_cast<uint32_t>(l));
      if (seen == TableVisibility::Hidden) continue;
    }
    sampler.setDimension(d0 + 2 * uint64_t(l));
    const Vec2 u = sampler.next2D();
    LightRecord rec;
    if (!lights.sample(light, hit.p, u, rec)) continue;
    const BSDFQuery q(frame.toLocal(rec.wi), woLocal);
    Color f = bsdf.eval(q);
    if (options.nonDiffuseOnly && q.wi.z * q.wo.z > 0.0f) f = glm::max(f - fDiffuse, Color(0.0f));
    if (maxComponent(f) <= 0.0f) continue;
    if (seen != TableVisibility::Visible) {
      ++rays;
      if (scene.occluded(shadowRay(hit, rec.wi, rec.distance))) continue;
    }
    const float weight = light.isDelta() || !options.mis ? 1.0f : powerHeuristic(rec.pdf, bsdf.pdf(q));
    sum += f * (std::abs(q.wi.z) * weight) * rec.value;
  }
  sampler.setDimension(d0 + 2 * uint64_t(lights.lights().size()));
  return sum;
}

}  // namespace fs
