// Next-event estimation, for every integrator (next_event.h).
#include "render/lights/next_event.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/firstshot/lighting.h"
#include "render/firstshot/patch_emitters.h"
#include "render/lights/light_sampler.h"

namespace firstshot {

namespace {

/// The contribution f·|cos θ_i|·weight·rec.value of the light sample @p rec at the shading point,
/// 0 if it is not finite, the BSDF sends nothing along it or (unless @p seen says Visible) a shadow
/// ray finds it occluded. @p delta: the sample came from a delta light (weight 1).
Color weighLightSample(const RenderScene& scene, const Hit& hit, const Frame& frame, const Vec3& woLocal,
                       const BSDF& bsdf, const LightRecord& rec, bool delta, TableVisibility seen,
                       const NeeRequest& request, uint64_t& rays) {
  if (!std::isfinite(rec.pdf) || !(maxComponent(rec.value) > 0.0f) || !std::isfinite(maxComponent(rec.value)))
    return Color(0.0f);
  const BSDFQuery q(frame.toLocal(rec.wi), woLocal);
  Color f = bsdf.eval(q);
  if (request.nonDiffuseOnly && q.wi.z * q.wo.z > 0.0f)
    f = glm::max(f - bsdf.diffuseAlbedo() * kInvPiF, Color(0.0f));
  if (!(maxComponent(f) > 0.0f)) return Color(0.0f);
  Color through(1.0f);  // thin glass on the way: its transmittance
  if (seen != TableVisibility::Visible) {
    ++rays;
    through = scene.transmittance(shadowRay(hit, rec.wi, rec.distance));
    if (!(maxComponent(through) > 0.0f)) return Color(0.0f);
  }
  const float weight = delta || !request.mis ? 1.0f : powerHeuristic(rec.pdf, bsdf.pdf(q));
  return f * (std::abs(q.wi.z) * weight) * rec.value * through;
}

/// The point of patch emitter @p e chosen with probability @p pSelect for @p u, seen from @p x:
/// rec.value = Le/pdf. False if it sends nothing towards @p x.
bool patchPoint(const LightSampler& lights, const Emitter& e, float pSelect, const Vec3& x, const Vec2& u,
                LightRecord& rec, Color& Le) {
  const RenderScene& scene = lights.scene();
  const Patch& p = scene.mesh().patches[e.index];
  const Vec3 y = lights.emitterPoint(e, u);
  const Vec3 d = y - x;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return false;
  rec.distance = std::sqrt(dist2);
  rec.wi = d / rec.distance;
  const float cosY = -glm::dot(patchSideNormal(p, e.sub), rec.wi);
  if (!(cosY > 0.0f)) return false;  // x is on the other side: that side is another emitter
  Le = patchRadiance(scene, lights.lighting(), e.index, y, -rec.wi);
  if (!(maxComponent(Le) > 0.0f)) return false;
  Le *= sampledPatchPointWeight(scene, e.index, y, -rec.wi);  // 0 where a surface lies on y (a probe ray)
  if (!(maxComponent(Le) > 0.0f)) return false;
  rec.pdf = pSelect * dist2 / (cosY * e.area);
  rec.value = Le / rec.pdf;
  return true;
}

/// A direction of the infinite light (LightSet::environment), chosen with probability @p pSelect, from @p u:
/// rec.value = L/pdf. False if the map sends nothing.
bool environmentDirection(const EnvironmentMap& env, float pSelect, const Vec2& u, LightRecord& rec) {
  float pdf = 0.0f;
  const Color L = env.sample(u, rec.wi, pdf);
  if (!(pdf > 0.0f) || !(maxComponent(L) > 0.0f)) return false;
  rec.distance = std::numeric_limits<float>::infinity();
  rec.pdf = pSelect * pdf;
  rec.value = L / rec.pdf;
  return true;
}

/// NEE to the chosen emitter @p c with the point from @p u ∈ [0,1)².
Color emitterContribution(const LightSampler& lights, const SampledEmitter& c, const Hit& hit, const Frame& frame,
                          const Vec3& woLocal, const BSDF& bsdf, const Vec2& u, const NeeRequest& request,
                          uint64_t& rays) {
  const RenderScene& scene = lights.scene();
  const Emitter& e = c.emitter;
  const float pSelect = c.p;
  LightRecord rec;
  bool delta = false;
  TableVisibility seen = TableVisibility::Unknown;
  if (lights.hasLuminaires() && (e.kind == Emitter::Kind::Light || e.kind == Emitter::Kind::Triangle)) {
    const int lum = scene.luminaires().ofLight(e.index);  // the Inner group, but the box the vertex's path entered
    if (lum >= 0 && lum == request.exceptLuminaire) return Color(0.0f);
  }
  switch (e.kind) {
    case Emitter::Kind::Light: {
      const RenderLight& light = scene.lights().lights()[e.index];
      if (request.tableVisibility && light.replaced && hit.onPatch()) {
        seen = lights.lighting().visibility(hit.patch, e.index);
        if (seen == TableVisibility::Hidden) return Color(0.0f);
      }
      if (!scene.lights().sample(light, hit.p, u, rec)) return Color(0.0f);
      rec.value /= pSelect;
      rec.pdf *= pSelect;
      delta = light.isDelta();
      break;
    }
    case Emitter::Kind::Triangle: {
      const RenderLight& light = scene.lights().lights()[e.index];
      const Vec3 d = lights.emitterPoint(e, u) - hit.p;
      const float dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0f)) return Color(0.0f);
      rec.distance = std::sqrt(dist2);
      rec.wi = d * (1.0f / rec.distance);  // one division, not three (a hot path)
      const float cosL = -glm::dot(lights.triangle(e).n, rec.wi);
      if (!(cosL > 0.0f)) return Color(0.0f);
      // pdf and 1/pdf from the same inputs: two independent divisions instead of one after the other.
      rec.pdf = pSelect * dist2 / (cosL * e.area);
      const Color le = light.textured ? lights.emitterRadiance(e, u) : light.radiance;  // per point
      rec.value = le * (cosL * e.area / (pSelect * dist2));
      break;
    }
    case Emitter::Kind::Patch: {
      Color Le;
      if (!patchPoint(lights, e, pSelect, hit.p, u, rec, Le)) return Color(0.0f);
      break;
    }
    case Emitter::Kind::Environment:
      if (!environmentDirection(*scene.lights().environment(), pSelect, u, rec)) return Color(0.0f);
      break;
    case Emitter::Kind::Exit: {
      const LuminaireBoxes& boxes = scene.luminaires();
      uint32_t k = 0;
      float pPatch = 0.0f;
      Vec2 uPoint = u;
      if (!boxes.choosePatch(e.index, hit.p, uPoint.x, k, pPatch)) return Color(0.0f);
      const Luminaire& lum = boxes.items()[e.index];
      const ExitPatch p = lum.patch(k);
      const Vec3 d = p.point(uPoint) - hit.p;
      const float dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0f)) return Color(0.0f);
      rec.distance = std::sqrt(dist2);
      rec.wi = d * (1.0f / rec.distance);
      const float cosY = -glm::dot(p.normal, rec.wi);
      if (!(cosY > 0.0f)) return Color(0.0f);  // x is inside the box or beside this face
      const Color le = lum.radianceAt(k, -rec.wi);
      if (!(maxComponent(le) > 0.0f)) return Color(0.0f);
      rec.pdf = pSelect * pPatch * dist2 / (cosY * p.area);
      rec.value = le / rec.pdf;
      break;
    }
    case Emitter::Kind::Gonio: {  // a point source at the centre, seen up to where the ray enters the box
      const Luminaire& lum = scene.luminaires().items()[e.index];
      if (lum.contains(hit.p)) return Color(0.0f);  // inside: the path sees the luminaire as it is
      const Vec3 d = lum.centre - hit.p;
      const float dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0f)) return Color(0.0f);
      const float dist = std::sqrt(dist2);
      rec.wi = d * (1.0f / dist);
      float tEntry = dist;
      int face = 0;
      if (!lum.entry(hit.p, rec.wi, dist * 1.0001f, tEntry, face)) tEntry = dist;
      rec.distance = tEntry;
      rec.pdf = pSelect;
      rec.value = lum.intensityAt(-rec.wi) / (dist2 * pSelect);
      delta = true;
      break;
    }
  }
  return weighLightSample(scene, hit, frame, woLocal, bsdf, rec, delta, seen, request, rays);
}

}  // namespace

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

Color nextEventEveryLight(const RenderScene& scene, const FirstShotLighting& lighting,
                          const std::vector<uint8_t>* include, const Hit& hit, const Frame& frame, const Vec3& woLocal,
                          const BSDF& bsdf, const NeeRequest& request, Sampler& sampler, uint64_t& rays,
                          NeeParts* parts) {
  const LightSet& lights = scene.lights();
  Color sum(0.0f);
  // Light l takes dimensions d0 + 2l and d0 + 2l + 1 (later dimensions do not shift); the lights
  // left out skip theirs without drawing them.
  const uint64_t d0 = sampler.dimension();
  const bool useTable = request.tableVisibility && hit.onPatch();
  TableVisibilityMap::Cursor table;
  if (useTable) table = lighting.visibilityCursor(hit.patch);
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const RenderLight& light = lights.lights()[l];
    if (!(light.replaced ? request.replaced : request.kept)) continue;
    if (include && !(*include)[l]) continue;
    TableVisibility seen = TableVisibility::Unknown;
    if (useTable && light.replaced) {
      seen = table.next(static_cast<uint32_t>(l));
      if (seen == TableVisibility::Hidden) continue;
    }
    sampler.setDimension(d0 + 2 * uint64_t(l));
    const Vec2 u = sampler.next2D();
    LightRecord rec;
    if (!lights.sample(light, hit.p, u, rec)) continue;
    const Color c = weighLightSample(scene, hit, frame, woLocal, bsdf, rec, light.isDelta(), seen, request, rays);
    sum += c;
    if (parts) (light.replaced ? parts->replaced : parts->kept) += c;
  }
  sampler.setDimension(d0 + 2 * uint64_t(lights.lights().size()));
  // The infinite light, after the lights (scenes without one draw exactly as before), with every light included.
  const EnvironmentMap* env = lights.environment();
  if (env && request.kept &&
      (!include || request.infinite || std::all_of(include->begin(), include->end(), [](uint8_t i) { return i != 0; }))) {
    LightRecord rec;
    if (environmentDirection(*env, 1.0f, sampler.next2D(), rec)) {
      const Color c =
          weighLightSample(scene, hit, frame, woLocal, bsdf, rec, false, TableVisibility::Unknown, request, rays);
      sum += c;
      if (parts) parts->environment += c;
    }
  }
  return sum;
}

Color nextEventEveryLuminaire(const LightSampler& lights, const Hit& hit, const Frame& frame, const Vec3& woLocal,
                              const BSDF& bsdf, const NeeRequest& request, Sampler& sampler, uint64_t& rays) {
  if (!lights.hasLuminaires()) return Color(0.0f);
  const std::vector<Luminaire>& items = lights.scene().luminaires().items();
  Color sum(0.0f);
  // Luminaire i takes dimensions d0 + 2i and d0 + 2i + 1 for its exit patch (its specular light needs none).
  const uint64_t d0 = sampler.dimension();
  for (uint32_t i = 0; i < items.size(); ++i) {
    sampler.setDimension(d0 + 2 * uint64_t(i));
    const Vec2 u = sampler.next2D();
    if (luminance(items[i].exitPower) > 0.0f)
      sum += emitterContribution(lights, SampledEmitter{Emitter{Emitter::Kind::Exit, i, i, 0.0f}, 1.0f}, hit, frame,
                                 woLocal, bsdf, u, request, rays);
    if (luminance(items[i].specularPower) > 0.0f)
      sum += emitterContribution(lights, SampledEmitter{Emitter{Emitter::Kind::Gonio, i, i, 0.0f}, 1.0f}, hit, frame,
                                 woLocal, bsdf, u, request, rays);
  }
  sampler.setDimension(d0 + 2 * uint64_t(items.size()));
  return sum;
}

Color nextEvent(const LightSampler& lights, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                const NeeRequest& request, Sampler& sampler, uint64_t& rays, NeeParts* parts) {
  const Vec3 n = receiverNormal(bsdf, woLocal.z >= 0.0f ? hit.ng : -hit.ng);  // the side that reflects towards the viewer
  Color sum(0.0f);
  auto fromGroup = [&](LightGroup g) {
    if (lights.empty(g)) {  // skip its two dimensions without drawing them (images stay the same)
      sampler.setDimension(sampler.dimension() + 2);
      return;
    }
    // One stratified pair for the choice and the point: x chooses the emitter and, rescaled within
    // the chosen emitter's share, is the point's first number; y its second.
    const Vec2 a = sampler.next2D();
    SampledEmitter c;
    float rest = 0.0f;
    if (!lights.sample(g, hit.p, n, a.x, c, &rest)) return;
    const Color term = emitterContribution(lights, c, hit, frame, woLocal, bsdf, Vec2(rest, a.y), request, rays);
    sum += term;
    if (parts)
      (c.emitter.kind == Emitter::Kind::Environment ? parts->environment
       : g == LightGroup::Patches                  ? parts->patches
       : g == LightGroup::Replaced                 ? parts->replaced
                                                   : parts->kept) += term;
  };
  if (lights.strategy() == LightStrategy::All) {
    if (request.kept || request.replaced)
      sum += nextEventEveryLight(lights.scene(), lights.lighting(), &lights.included(), hit, frame, woLocal, bsdf,
                                 request, sampler, rays, parts);
  } else {
    if (request.kept) fromGroup(LightGroup::Kept);
    if (request.replaced) fromGroup(LightGroup::Replaced);
    if (request.inner && lights.hasLuminaires()) fromGroup(LightGroup::Inner);
  }
  if (request.patches && lights.hasPatchGroup()) fromGroup(LightGroup::Patches);
  return sum;
}

float nextEventPdf(const LightSampler& lights, const Vec3& x, const Vec3& n, const NeeRequest& request, const Hit& y) {
  const Vec3 d = y.p - x;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return 0.0f;
  const float cosY = std::abs(glm::dot(y.ng, d)) / std::sqrt(dist2);
  if (!(cosY > 0.0f)) return 0.0f;
  const RenderLight* light = nullptr;
  if (y.onPatch()) {
    if (!request.patches) return 0.0f;
  } else {
    light = &lights.scene().lights().emitterLight(y.emitter);
    const int lum = lights.hasLuminaires()
                        ? lights.scene().luminaires().ofLight(uint32_t(light - lights.scene().lights().lights().data()))
                        : -1;
    if (lum >= 0) {
      if (!request.inner || lum == request.exceptLuminaire) return 0.0f;
    } else if (!(light->replaced ? request.replaced : request.kept)) {
      return 0.0f;
    }
    if (glm::dot(y.ng, d) >= 0.0f) return 0.0f;  // one-sided: x is behind the emitter
  }
  float area = 0.0f;
  const float p = lights.pmf(x, n, y, area);
  if (!(p > 0.0f)) return 0.0f;
  // Every light (p = 1): the light's own density of the point.
  if (light && lights.strategy() == LightStrategy::All) return lights.scene().lights().pdf(*light, x, y.p, y.ng);
  return p * dist2 / (cosY * area);
}

float nextEventExitPdf(const LightSampler& lights, const Vec3& x, const Vec3& n, const NeeRequest& request,
                       uint32_t exit, const Vec3& y) {
  if (!request.kept || !lights.hasLuminaires()) return 0.0f;
  const LuminaireBoxes& boxes = lights.scene().luminaires();
  const uint32_t i = boxes.exitLuminaire(exit);
  const Vec3 d = y - x;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return 0.0f;
  const float cosY = std::abs(glm::dot(boxes.items()[i].patch(exit - boxes.exitFirst(i)).normal, d)) / std::sqrt(dist2);
  if (!(cosY > 0.0f)) return 0.0f;
  float area = 0.0f;
  const float p = lights.exitPmf(x, n, exit, area);
  return p > 0.0f ? p * dist2 / (cosY * area) : 0.0f;
}

float nextEventEnvironmentPdf(const LightSampler& lights, const NeeRequest& request, const Vec3& dir) {
  const EnvironmentMap* env = lights.scene().lights().environment();
  if (!env || !request.kept) return 0.0f;
  const float p = lights.environmentPmf();
  return p > 0.0f ? p * env->pdf(dir) : 0.0f;
}

bool samplePatchEmitter(const LightSampler& lights, const Vec3& x, const Vec3& n, const Vec3& u, PatchSample& s) {
  SampledEmitter c;
  if (!lights.sample(LightGroup::Patches, x, n, u.x, c)) return false;  // patches only: no directional lights
  LightRecord rec;
  if (!patchPoint(lights, c.emitter, c.p, x, Vec2(u.y, u.z), rec, s.Le)) return false;
  if (!std::isfinite(rec.pdf) || !std::isfinite(maxComponent(rec.value))) return false;
  s.wi = rec.wi;
  s.distance = rec.distance;
  s.pdf = rec.pdf;
  return true;
}

}  // namespace firstshot
