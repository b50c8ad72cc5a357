// Table mode of the shooting integrators: the small lights' own part of a camera subpath.
#include "render/integrators/common/small_lights.h"

#include "render/firstshot/patch_emitters.h"
#include "render/lights/next_event.h"

namespace firstshot {

void SmallLightsExact::build(const RenderScene& scene, const FirstShotLighting& lighting,
                             const IntegratorOptions& options) {
  scene_ = &scene;
  lights_.build(scene, lighting, options.lightSampler, false, options.lightVisibility);
  request_.tableVisibility = options.tableVisibility;
  polished_ = mayBePolished(scene);
}

bool SmallLightsExact::gathers(std::span<const SubpathVertex> camera, size_t i, size_t m, size_t polishedUpTo) const {
  if (i == m) return true;
  return polished_ && i > m && i <= polishedUpTo && i < camera.size() && !camera[i].delta &&
         scene_->bsdfAt(camera[i].hit).tooSharpForTable();
}

Color SmallLightsExact::estimate(std::span<const SubpathVertex> camera, size_t m, Sampler& sampler, uint64_t& rays,
                                 size_t polishedUpTo, bool skipDeltaChains) const {
  const LightSet& lights = scene_->lights();
  Color L(0.0f);
  for (size_t i = 1; i < camera.size(); ++i) {
    const SubpathVertex& v = camera[i];
    if (v.hit.onPatch() || !lights.emitterLight(v.hit.emitter).replaced) continue;
    const Color Le = lights.emitted(v.hit, v.wi);
    if (!(maxComponent(Le) > 0.0f)) continue;
    float weight = 1.0f;
    if (i > m && gathers(camera, i - 1, m, polishedUpTo)) {  // a BSDF sample against its vertex's NEE
      const SubpathVertex& x = camera[i - 1];
      const Frame frame = scene_->shadingFrame(x.hit);
      const Vec3 wi = glm::normalize(v.hit.p - x.hit.p);
      const BSDF bsdfX = scene_->bsdfAt(x.hit);
      const float pdfBsdf = bsdfX.pdf(BSDFQuery(frame.toLocal(wi), frame.toLocal(x.wi)));
      const Vec3 n = receiverNormal(bsdfX, glm::dot(x.wi, x.hit.ng) >= 0.0f ? x.hit.ng : -x.hit.ng);
      const float pdfLight = nextEventPdf(lights_, x.hit.p, n, request_, v.hit);
      weight = pdfLight > 0.0f ? powerHeuristic(pdfBsdf, pdfLight) : 1.0f;
    } else if (i > m + 1 && !camera[i - 1].delta) {
      continue;  // the table holds it
    } else if (skipDeltaChains && afterDeltaChain(camera, i, m)) {
      continue;  // the caller weights it against its light subpaths through the same mirrors and glass
    }
    L += v.beta * Le * weight;
  }
  for (size_t i = m; i < camera.size() && (i == m || (polished_ && i <= polishedUpTo)); ++i) {
    if (!gathers(camera, i, m, polishedUpTo)) continue;
    const SubpathVertex& x = camera[i];
    const Frame frame = scene_->shadingFrame(x.hit);
    L += x.beta * nextEvent(lights_, x.hit, frame, frame.toLocal(x.wi), scene_->bsdfAt(x.hit), request_, sampler, rays);
  }
  return L;
}

}  // namespace firstshot
