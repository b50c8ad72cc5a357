// NEE and the first-shot term, shared by the integrators.
#include "render/direct_light.h"

#include <algorithm>
#include <cmath>

namespace fs {

Ray shadowRay(const Hit& hit, const Vec3& wi, float distance) {
  const float tmax = std::isinf(distance) ? distance : distance * (1.0f - 1e-4f) - hit.eps;
  return Ray(hit.spawnOrigin(wi), wi, 0.0f, tmax);
}

void FirstShotLighting::build(const RenderScene& scene) {
  scene_ = &scene;
  const FirstShotTable* t = scene.firstShot();
  sideIrradiance_ = t ? t->sideIrradiance() : std::vector<Color>();
}

Color FirstShotLighting::eval(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const {
  if (bsdf.isDiffuse()) {
    // f = ρ/π for every sample on the viewer's side, 0 for the others.
    const bool front = woLocal.z > 0.0f;
    const Color f = bsdf.eval(BSDFQuery(Vec3(0.0f, 0.0f, front ? 1.0f : -1.0f), woLocal));
    return f * sideIrradiance_[2 * size_t(hit.patch) + (front ? 0 : 1)];
  }
  const FirstShotTable& t = *scene_->firstShot();
  Color sum(0.0f);
  for (uint64_t k = t.rowStart[hit.patch], end = t.rowStart[hit.patch + 1]; k < end; ++k) {
    const LightSample& s = t.samples[t.sampleIndex[k]];
    const Vec3 wi = s.kind == LightSampleKind::Directional ? -s.normal : glm::normalize(s.position - hit.p);
    const Color f = bsdf.eval(BSDFQuery(frame.toLocal(wi), woLocal));
    sum += s.emission * (t.factor[k] * f);
  }
  return sum;
}

Color estimateDirect(const RenderScene& scene, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                     const DirectLightOptions& options, Sampler& sampler, uint64_t& rays) {
  const LightSet& lights = scene.lights();
  const Color fDiffuse = options.nonDiffuseOnly ? bsdf.diffuseAlbedo() * kInvPiF : Color(0.0f);
  Color sum(0.0f);
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const RenderLight& light = lights.lights()[l];
    const Vec2 u = sampler.next2D();  // drawn for every light, so later dimensions do not shift
    if (options.skipReplaced && light.replaced) continue;
    if (options.include && !(*options.include)[l]) continue;
    LightRecord rec;
    if (!lights.sample(light, hit.p, u, rec)) continue;
    const BSDFQuery q(frame.toLocal(rec.wi), woLocal);
    Color f = bsdf.eval(q);
    if (options.nonDiffuseOnly && q.wi.z * q.wo.z > 0.0f) f = glm::max(f - fDiffuse, Color(0.0f));
    if (maxComponent(f) <= 0.0f) continue;
    ++rays;
    if (scene.occluded(shadowRay(hit, rec.wi, rec.distance))) continue;
    const float weight = light.isDelta() || !options.mis ? 1.0f : powerHeuristic(rec.pdf, bsdf.pdf(q));
    sum += f * (std::abs(q.wi.z) * weight) * rec.value;
  }
  return sum;
}

}  // namespace fs
