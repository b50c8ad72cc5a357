// Luminaires in the irradiance cache: their light is direct light, taken by NEE at every shaded point, so that the
// records' hemisphere rays never have to find it (a filament behind glass met by a ray that refracts into it, a bowl's
// opening). A record's or glossy ray that enters a box and meets something inside counts nothing of the luminaire's
// light there: its exit light, specular light and lights were the shaded point's NEE. What the inside of the box
// reflects of the room's other light still counts, traced by the path continuation with the luminaire's lights
// suppressed, as the path tracer does past a counted entry (render/scene/luminaire_boxes.h). A box entered from the
// camera or after a mirror or glass is seen as it is, as everywhere.
#include "render/integrators/irradiance_cache/context.h"
#include "render/integrators/irradiance_cache/integrator.h"

namespace firstshot {

bool IrradianceCacheIntegrator::holdsNonLambertian(const RenderScene& scene, const Luminaire& l) {
  const std::vector<MaterialDesc>& materials = scene.desc().materials;
  for (const Patch& p : scene.mesh().patches) {
    if (p.material >= materials.size() || materials[p.material].type == MaterialType::Diffuse) continue;
    if (l.contains(p.centroid)) return true;
  }
  return false;
}

Color IrradianceCacheIntegrator::enteredLuminaire(const Ray& ray, const Hit& hit, const BSDF& bsdf, const Color& beta,
                                                  int vertex, Sampler& sampler, Context& ctx, FirstVertex* first) const {
  // The first-shot term of the hit, which the walk counts in full (its vertex took no patch NEE): what patch NEE at
  // the record weighs against (patch_nee.cpp). As the walk's rule for using the table there.
  const FirstShotTable* table = scene_->firstShot();
  if (first && patchNeeOn() && hit.onPatch() && !table->replacedLights.empty() && !bsdf.hasDelta() &&
      !bsdf.tooSharpForTable()) {
    const Frame frame = scene_->shadingFrame(hit);
    first->firstShot = firstShot_.eval(hit, frame, frame.toLocal(-glm::normalize(ray.d)), bsdf);
  }
  PathVertex from;
  from.delta = false;
  from.p = ray.o;
  from.counted = &direct_;  // the luminaires' lights among them
  from.countedInfinite = true;
  from.countedExits = true;
  return continuation_.trace(ray, beta, vertex, from, false, sampler, ctx.rays, nullptr, &hit);
}

Color IrradianceCacheIntegrator::LiFromSensor(const Ray& ray, const PathVertex& from, Sampler& sampler,
                                              SampleInfo* info) const {
  if (!luminaires_) return Li(ray, sampler, info);
  uint64_t rays = 0;
  const Color L = continuation_.trace(ray, Color(1.0f), 0, from, false, sampler, rays, info);
  if (info) info->rays = rays;
  return L;
}

}  // namespace firstshot
