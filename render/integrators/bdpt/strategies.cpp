// Contributions of the bidirectional strategies with t ≥ 2.
#include "render/integrators/bdpt/strategies.h"

#include <cmath>
#include <limits>

#include "common/lights/spot_cone.h"
#include "render/lights/next_event.h"

namespace firstshot {

namespace {

/// s = 1 at an exit patch: its luminaire kept, the patch chosen again as the path tracer's next-event estimation
/// chooses it for a receiver at @p x (LuminaireBoxes::choosePatch: mostly by what the patches send towards x), a point
/// uniform on it; @p es's probabilities are the choice's. The MIS weights keep the densities of a light subpath's
/// origin (the exit patches' own s = 0 is none, so no weight reads this choice's): any weights that sum to one over a
/// path's strategies keep the sum unbiased.
bool chooseExitPatch(const BdptDensities& densities, const Vec3& x, Sampler& sampler, EmissionSample& es) {
  const EmissionSampler& emission = densities.emission();
  const LuminaireBoxes& boxes = densities.scene().luminaires();
  const uint32_t luminaire = boxes.exitLuminaire(es.light - emission.exitBegin());
  float u = sampler.next1D(), p = 0.0f;
  uint32_t k = 0;
  const Vec2 uPos = sampler.next2D();
  if (!boxes.choosePatch(luminaire, x, u, k, p)) return false;
  es.light = emission.exitBegin() + boxes.exitFirst(luminaire) + k;
  const ExitPatch& patch = emission.exits().patch(es.light - emission.exitBegin());
  es.p = patch.point(uPos);
  es.n = patch.normal;
  es.pdfLight = emission.luminaireChoice(luminaire) * p;
  es.pdfPos = 1.0f / patch.area;
  return es.pdfLight > 0.0f;
}

}  // namespace

Color connectEmission(const BdptDensities& densities, const SubpathVertex& pt, bool patchEmits) {
  if (pt.kind != SubpathVertex::Kind::Surface) return Color(0.0f);
  const EmissionSampler& emission = densities.emission();
  if (pt.hit.onPatch()) {
    if (!patchEmits) return Color(0.0f);
    const uint32_t e = densities.lightOf(pt);
    return e == kNoId ? Color(0.0f) : pt.beta * emission.patchRadiance(e, pt.hit.p, pt.wi);
  }
  if (!(emission.power(densities.lightOf(pt)) > 0.0)) return Color(0.0f);  // a replaced light in table mode
  return pt.beta * densities.scene().lights().emitted(pt.hit, pt.wi);
}

Color connectLightSample(const BdptDensities& densities, const SubpathVertex& pt, Sampler& sampler,
                         SubpathVertex& sampled, uint64_t& rays) {
  const Vec2d uPair = sampler.next2Dd();  // the light and its point from one stratified pair
  EmissionSample es;
  const EmissionSampler& emission = densities.emission();
  if (pt.delta || !emission.sampleOrigin(uPair, es)) return Color(0.0f);
  if (emission.isExit(es.light) && !chooseExitPatch(densities, pt.hit.p, sampler, es)) return Color(0.0f);
  sampled = SubpathVertex();
  sampled.kind = SubpathVertex::Kind::Light;
  sampled.light = es.light;
  sampled.hit.p = es.p;
  sampled.hit.ng = es.n;
  sampled.pdfFwd = es.pdfLight * es.pdfPos;
  sampled.deltaLight = es.deltaPosition || es.deltaDirection;
  sampled.deltaDirection = es.deltaDirection;
  sampled.exitPatch = emission.isExit(es.light);

  // Incident radiance-like weight from the light, over p_light (and p_pos): Le·G/p or I/(d²·p) or E/p.
  Vec3 wi;
  float distance = std::numeric_limits<float>::infinity();
  Color incident(0.0f);
  if (emission.isExit(es.light) || emission.isPatch(es.light)) {  // an exit patch (0 into its box) or a lit patch
    const Vec3 d = es.p - pt.hit.p;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return Color(0.0f);
    distance = std::sqrt(dist2);
    wi = d / distance;
    const float cosLight = -glm::dot(es.n, wi);
    if (!(cosLight > 0.0f)) return Color(0.0f);
    const float toIncident = cosLight / (dist2 * es.pdfLight * es.pdfPos);
    if (emission.isExit(es.light)) {
      incident = emission.exitRadiance(es.light, -wi) * toIncident;
    } else {
      incident = emission.patchRadiance(es.light, es.p, -wi) * toIncident;
      if (maxComponent(incident) > 0.0f) incident *= emission.coverage(es.light, es.p, -wi);  // its probe ray only then
    }
  } else if (es.deltaDirection) {
    const RenderLight& light = densities.scene().lights().lights()[es.light];
    wi = -light.direction;
    incident = light.irradiance / es.pdfLight;
  } else {
    const RenderLight& light = densities.scene().lights().lights()[es.light];
    const Vec3 d = es.p - pt.hit.p;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return Color(0.0f);
    distance = std::sqrt(dist2);
    wi = d / distance;
    switch (light.type) {
      case LightType::Area: {
        const float cosLight = -glm::dot(es.n, wi);
        if (!(cosLight > 0.0f)) return Color(0.0f);
        incident = es.radiance * (cosLight / dist2);
        break;
      }
      case LightType::Spot:
        incident = light.intensity * light.profile(-wi) / (es.pdfLight * dist2);
        break;
      default: incident = light.intensity / (es.pdfLight * dist2); break;
    }
  }
  const Frame frame = densities.scene().shadingFrame(pt.hit);  // cos θ about the shading normal
  const BSDFQuery q(frame.toLocal(wi), frame.toLocal(pt.wi));
  const Color L = pt.beta * densities.scene().bsdfAt(pt.hit).eval(q) * incident * std::abs(glm::dot(frame.n, wi));
  if (!(maxComponent(L) > 0.0f)) return Color(0.0f);
  ++rays;
  const Color through = densities.scene().transmittance(shadowRay(pt.hit, wi, distance));  // thin glass: its T
  return maxComponent(through) > 0.0f ? L * through : Color(0.0f);
}

Color connectVertices(const BdptDensities& densities, const SubpathVertex& qs, const SubpathVertex& pt,
                      uint64_t& rays) {
  if (qs.delta || pt.delta) return Color(0.0f);
  const Vec3 d = qs.hit.p - pt.hit.p;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return Color(0.0f);
  const float distance = std::sqrt(dist2);
  const Vec3 w = d / distance;  // from pt to qs
  const RenderScene& scene = densities.scene();
  const Frame fp = scene.shadingFrame(pt.hit), fq = scene.shadingFrame(qs.hit);
  const Color fCamera = scene.bsdfAt(pt.hit).eval(BSDFQuery(fp.toLocal(w), fp.toLocal(pt.wi)));
  const BSDF bsdfLight = scene.bsdfAt(qs.hit);
  // f(light side → camera side) with wi towards the light: the radiance BSDF (rough glass's η²).
  const Color fLight = bsdfLight.eval(BSDFQuery(fq.toLocal(qs.wi), fq.toLocal(-w), TransportMode::Radiance));
  // The camera side's cosine about its shading normal; the light side's f·|cos| with the adjoint factor
  // (render/scene/shading_normals.h) is f·|w·n_g|·|ω_prev·n_s|/|ω_prev·n_g|.
  float G = std::abs(glm::dot(fp.n, w)) * std::abs(glm::dot(qs.hit.ng, w)) / dist2;
  if (bsdfLight.shaded()) G *= adjointCorrection(qs.wi, -w, fq.n, qs.hit.ng) * std::abs(glm::dot(fq.n, w)) /
                               std::abs(glm::dot(qs.hit.ng, w));
  const Color L = pt.beta * fCamera * fLight * qs.beta * G;
  if (!(maxComponent(L) > 0.0f)) return Color(0.0f);
  ++rays;
  const Color through = scene.transmittance(shadowRay(pt.hit, w, distance));  // thin glass: its T
  return maxComponent(through) > 0.0f ? L * through : Color(0.0f);
}

}  // namespace firstshot
