// Emission sampling: a light by power, then a point and a direction.
#include "render/lights/light_emission.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/lights/spot_cone.h"
#include "common/sampling/sampling.h"
#include "common/table/firstshot.h"
#include "render/firstshot/patch_emitters.h"
#include "render/scene/render_scene.h"

namespace firstshot {

namespace {

float mean(const Color& c) { return (c.x + c.y + c.z) / 3.0f; }

/// The light centre of side @p side of patch @p j: the mean of its light samples' positions on that side
/// of its plane, weighted by e_i·r_ij (directional samples have none); NaN if no sample lights it.
Vec3 lightCentre(const FirstShotTable& table, uint32_t j, uint32_t side) {
  const Patch& p = table.mesh.patches[j];
  const Vec3 n = patchSideNormal(p, side);
  Vec3d sum(0.0);
  double weight = 0;
  for (uint64_t k = table.rowStart[j]; k < table.rowStart[j + 1]; ++k) {
    const LightSample& s = table.samples[table.sampleIndex[k]];
    if (s.kind == LightSampleKind::Directional || !(glm::dot(s.position - p.centroid, n) > 0.0f)) continue;
    const double w = double(mean(s.emission)) * table.factor[k];
    sum += w * Vec3d(s.position), weight += w;
  }
  return weight > 0 ? Vec3(sum / weight) : Vec3(std::numeric_limits<float>::quiet_NaN());
}

/// The hit of a point @p y on patch @p j, as patchRadiance() evaluates it (render/firstshot/patch_emitters.h).
Hit patchHit(const PatchMesh& mesh, uint32_t j, const Vec3& y) {
  Hit hit;
  hit.p = y;
  hit.ng = mesh.patches[j].normal;
  hit.patch = j;
  return hit;
}

/// Unit direction from @p y to the light centre @p c; the side's normal @p n where they coincide.
Vec3 towardsCentre(const Vec3& y, const Vec3& c, const Vec3& n) {
  const Vec3 v = c - y;
  const float len2 = glm::dot(v, v);
  return len2 > 0.0f ? v / std::sqrt(len2) : n;
}

}  // namespace

EmissionSampler::EmissionSampler(const LightSet& lights, const SceneDesc& scene, EmitterSet set) : lights_(&lights) {
  setBounds(scene);
  addLights(set);
  finish();
}

EmissionSampler::EmissionSampler(const RenderScene& scene, const FirstShotLighting& lighting)
    : lights_(&scene.lights()), scene_(&scene), lighting_(&lighting) {
  setBounds(scene.desc());
  addLights(EmitterSet::Kept);
  const PatchMesh& mesh = scene.mesh();
  sideEmitter_.assign(2 * size_t(mesh.size()), kNoId);
  if (const FirstShotTable* table = scene.firstShot()) {
    const std::vector<Color> side = table->sideIrradiance();
    for (uint32_t j = 0; j < mesh.size(); ++j)
      for (uint32_t sd = 0; sd < 2; ++sd) {
        const float phi = patchSidePower(scene, side, j, sd);
        if (!(phi > 0.0f)) continue;
        sideEmitter_[2 * size_t(j) + sd] = uint32_t(power_.size());
        patchSides_.push_back(2 * j + sd);
        power_.push_back(phi);
        glossyCentre_.push_back(scene.patchBsdf(j).isDiffuse() ? Vec3(std::numeric_limits<float>::quiet_NaN())
                                                                : lightCentre(*table, j, sd));
      }
  }
  finish();
}

void EmissionSampler::addExits(const LuminaireBoxes& boxes, const std::vector<double>& innerShares) {
  if (boxes.empty()) return;
  exits_ = ExitEmission(boxes);
  exitBegin_ = uint32_t(power_.size());
  const size_t n = boxes.items().size();
  split_.assign(n, true);
  for (size_t i = 0; i < n && !innerShares.empty(); ++i) split_[i] = innerShares[i] > 0;
  luminairePower_.assign(n, 0.0);
  for (uint32_t e = 0; e < exits_.count(); ++e) {
    const uint32_t i = boxes.exitLuminaire(e);
    power_.push_back(split_[i] ? exits_.power(e) : 0.0);
    luminairePower_[i] += power_.back();
  }
  // A split luminaire's lights' particles light the inside of its box and, straight out of it, the room (the direct
  // light, not in its exit distribution): they are chosen by the share given, or by the share of their power that
  // does not leave it after a bounce inside (at least kMinInnerShare), their power weight growing to match.
  for (uint32_t l = 0; l < lightCount_; ++l) {
    const int i = boxes.ofLight(l);
    if (i < 0 || !split_[size_t(i)]) continue;
    if (!innerShares.empty()) {
      power_[l] *= innerShares[size_t(i)];
      continue;
    }
    const Luminaire& lum = boxes.items()[size_t(i)];
    const double emitted = mean(lum.power), left = mean(lum.exitPower);
    power_[l] *= emitted > 0 ? std::clamp(1.0 - left / emitted, kMinInnerShare, 1.0) : 1.0;
  }
  finish();
}

void EmissionSampler::setBounds(const SceneDesc& scene) {
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  centre_ = Vec3(0.5 * (lo + hi));
  radius_ = std::max(1e-6f, float(0.5 * glm::length(hi - lo)) * 1.01f);
}

void EmissionSampler::addLights(EmitterSet set) {
  for (const RenderLight& l : lights_->lights()) {
    double p = 0;
    switch (l.type) {
      case LightType::Point:
      case LightType::Spot: p = mean(l.intensity) * l.profile.integral(); break;
      case LightType::Directional: p = mean(l.irradiance) * kPi * double(radius_) * radius_; break;
      case LightType::Area: p = mean(l.radiance) * l.area * kPi; break;
    }
    const bool emits = set == EmitterSet::All || (set == EmitterSet::Kept && !l.replaced) ||
                       (set == EmitterSet::ReplacedAreaLights && l.replaced && l.type == LightType::Area) ||
                       (set == EmitterSet::Replaced && l.replaced);
    power_.push_back(emits ? std::max(0.0, p) : 0.0);
  }
  lightCount_ = uint32_t(power_.size());
}

void EmissionSampler::finish() { choice_ = Distribution1D(power_); }

void EmissionSampler::reweight(const std::vector<double>& factor) {
  for (size_t e = 0; e < power_.size() && e < factor.size(); ++e) power_[e] *= factor[e];
  std::fill(luminairePower_.begin(), luminairePower_.end(), 0.0);
  for (uint32_t e = 0; e < exits_.count(); ++e)
    luminairePower_[exits_.boxes()->exitLuminaire(e)] += power_[exitBegin_ + e];
  finish();
}

bool EmissionSampler::isDirectional(uint32_t e) const {
  return e < lightCount_ && lights_->lights()[e].type == LightType::Directional;
}

uint32_t EmissionSampler::patchEmitter(uint32_t j, uint32_t side) const {
  return 2 * size_t(j) + side < sideEmitter_.size() ? sideEmitter_[2 * size_t(j) + side] : kNoId;
}

Vec3 EmissionSampler::patchNormal(uint32_t e) const {
  const uint32_t ps = patchSides_[e - lightCount_];
  return patchSideNormal(scene_->mesh().patches[ps / 2], ps % 2);
}

float EmissionSampler::coverage(uint32_t e, const Vec3& y, const Vec3& w) const {
  return sampledPatchPointWeight(*scene_, patchOf(e), y, w);
}

Color EmissionSampler::patchRadiance(uint32_t e, const Vec3& y, const Vec3& w) const {
  if (!(glm::dot(patchNormal(e), w) > 0.0f)) return Color(0.0f);
  return firstshot::patchRadiance(*scene_, *lighting_, patchOf(e), y, w);
}

bool EmissionSampler::sampleOrigin(double u, const Vec2& uPos, EmissionSample& out) const {
  return choice_.total() > 0 && originOf(choice_.sampleDiscrete(u), uPos, out);
}

bool EmissionSampler::sampleOrigin(const Vec2d& uPair, EmissionSample& out) const {
  if (!(choice_.total() > 0)) return false;
  double rest = 0;  // the rest of uPair.x inside the emitter's CDF interval
  const size_t l = choice_.sampleDiscrete(uPair.x, &rest);
  return originOf(l, Vec2(std::min(float(rest), 0x1.fffffep-1f), float(uPair.y)), out);
}

bool EmissionSampler::originOf(size_t l, const Vec2& uPos, EmissionSample& out) const {
  if (!(power_[l] > 0)) return false;
  out = EmissionSample();
  out.light = static_cast<uint32_t>(l);
  out.pdfLight = float(power_[l] / choice_.total());
  out.pdfPos = pdfPosition(out.light);
  if (isExit(out.light)) {
    const ExitPatch& patch = exits_.patch(out.light - exitBegin_);
    out.p = patch.point(uPos);
    out.n = patch.normal;
    return true;
  }
  if (isPatch(out.light)) {
    out.p = samplePatchPoint(scene_->mesh().patches[patchOf(out.light)], uPos);
    out.n = patchNormal(out.light);
    return true;
  }
  const RenderLight& light = lights_->lights()[l];
  switch (light.type) {
    case LightType::Point:
    case LightType::Spot:
      out.p = light.position;
      out.deltaPosition = true;
      break;
    case LightType::Directional: {
      const Frame frame(light.direction);
      const Vec2 disk = squareToUniformDiskConcentric(uPos) * radius_;
      out.p = centre_ - radius_ * light.direction + frame.s * disk.x + frame.t * disk.y;
      out.n = light.direction;
      out.d = light.direction;
      out.deltaDirection = true;
      break;
    }
    case LightType::Area: {
      Color le;  // at the point (a textured emitter's texel)
      if (!lights_->samplePoint(light, uPos, out.p, out.n, &le)) return false;
      out.radiance = le / (out.pdfLight * out.pdfPos);
      break;
    }
  }
  return true;
}

float EmissionSampler::pdfPosition(uint32_t e) const {
  if (isExit(e)) return 1.0f / exits_.patch(e - exitBegin_).area;
  if (isPatch(e)) return float(1.0 / scene_->mesh().patches[patchOf(e)].area);
  const RenderLight& light = lights_->lights()[e];
  switch (light.type) {
    case LightType::Directional: return 1.0f / (kPiF * radius_ * radius_);
    case LightType::Area: return float(1.0 / light.area);
    default: return 1.0f;
  }
}

bool EmissionSampler::sampleGlossyPatch(uint32_t e, const Vec3& y, Vec2 u, Vec3& d, float& pdf) const {
  const Vec3 n = patchNormal(e);
  if (u.x < 0.5f) {  // the cosine half
    d = Frame(n).toWorld(squareToCosineHemisphere(Vec2(std::min(2.0f * u.x, 0x1.fffffep-1f), u.y)));
  } else {  // the BSDF's sample with ω_o towards the light centre (reciprocal: f(ω', ω) = f(ω, ω'))
    const Hit hit = patchHit(scene_->mesh(), patchOf(e), y);
    const Frame frame = scene_->shadingFrame(hit);
    BSDFQuery q(frame.toLocal(towardsCentre(y, glossyCentre_[e - lightCount_], n)));
    scene_->bsdfAt(hit).sample(q, Vec2(std::min(2.0f * u.x - 1.0f, 0x1.fffffep-1f), u.y));
    if (!(q.pdf > 0.0f)) return false;
    d = frame.toWorld(q.wi);
  }
  pdf = pdfGlossyPatch(e, y, d);
  return pdf > 0.0f && glm::dot(n, d) > 0.0f;
}

float EmissionSampler::pdfGlossyPatch(uint32_t e, const Vec3& y, const Vec3& d) const {
  const Hit hit = patchHit(scene_->mesh(), patchOf(e), y);
  const Frame frame = scene_->shadingFrame(hit);
  const Vec3 wo = towardsCentre(y, glossyCentre_[e - lightCount_], patchNormal(e));
  const float bsdfPdf = scene_->bsdfAt(hit).pdf(BSDFQuery(frame.toLocal(d), frame.toLocal(wo)));
  return 0.5f * std::max(0.0f, glm::dot(patchNormal(e), d)) * kInvPiF + 0.5f * bsdfPdf;
}

float EmissionSampler::pdfDirection(uint32_t e, const Vec3& y, const Vec3& n, const Vec3& d) const {
  if (isExit(e)) return exits_.pdfDirection(e - exitBegin_, d);
  if (isPatch(e)) {
    if (!std::isnan(glossyCentre_[e - lightCount_].x)) return pdfGlossyPatch(e, y, d);
    return std::max(0.0f, glm::dot(patchNormal(e), d)) * kInvPiF;
  }
  const RenderLight& light = lights_->lights()[e];
  switch (light.type) {
    case LightType::Point: return squareToUniformSpherePdf();
    case LightType::Spot: return float(light.profile.pdf(Vec3d(d)));
    case LightType::Area: return std::max(0.0f, glm::dot(n, d)) * kInvPiF;
    default: return 0.0f;
  }
}

bool EmissionSampler::sample(Sampler& sampler, EmissionSample& out, uint64_t stratum, uint64_t strata) const {
  const double u = std::min((double(stratum) + sampler.next1Dd()) / double(strata), 1.0);
  const Vec2 uPos = sampler.next2D();
  const Vec2 uDir = sampler.next2D();
  if (!(choice_.total() > 0)) return false;
  double rest = 0;
  if (!originOf(choice_.sampleDiscrete(u, &rest), uPos, out)) return false;
  if (isExit(out.light)) {
    // The bin by the rest of u inside the patch's CDF interval (53 bits: ample for 128 bins), the direction in the
    // bin by uDir. The power is the bin's radiance·cosθ over the densities (exit_emission.h: the same for all).
    ExitDirection dir;
    if (!exits_.sampleDirection(out.light - exitBegin_, rest, uDir, dir)) return false;
    out.d = dir.d;
    out.pdfDir = dir.pdf;
    out.power = dir.radiance * (std::abs(glm::dot(out.n, out.d)) / (out.pdfLight * out.pdfPos * out.pdfDir));
    return maxComponent(out.power) > 0.0f;
  }
  if (isPatch(out.light)) {
    float cosOut = 0;
    if (!std::isnan(glossyCentre_[out.light - lightCount_].x)) {
      if (!sampleGlossyPatch(out.light, out.p, uDir, out.d, out.pdfDir)) return false;
      cosOut = glm::dot(out.n, out.d);
    } else {
      const Vec3 local = squareToCosineHemisphere(uDir);
      out.d = Frame(out.n).toWorld(local);
      out.pdfDir = squareToCosineHemispherePdf(local);
      cosOut = local.z;
    }
    if (!(out.pdfDir > 0.0f)) return false;
    out.power = patchRadiance(out.light, out.p, out.d) * (cosOut / (out.pdfLight * out.pdfPos * out.pdfDir));
    // The coverage (and its probe ray) only for a particle that carries power.
    if (maxComponent(out.power) > 0.0f) out.power *= coverage(out.light, out.p, out.d);
    return maxComponent(out.power) > 0.0f;
  }
  const RenderLight& light = lights_->lights()[out.light];
  switch (light.type) {
    case LightType::Point: {
      out.d = squareToUniformSphere(uDir);
      out.pdfDir = squareToUniformSpherePdf();
      out.power = light.intensity / (out.pdfLight * out.pdfDir);
      break;
    }
    case LightType::Spot: {  // the profile's own distribution (cone or IES table), common/lights/emission_profile.h
      double pdf = 0;
      const Vec3d d = light.profile.sample(uDir.x, uDir.y, pdf);
      if (!(pdf > 0)) return false;
      out.d = Vec3(d);
      out.pdfDir = float(pdf);
      out.power = light.intensity * float(light.profile(d) / pdf) / out.pdfLight;
      break;
    }
    case LightType::Directional: {
      out.pdfDir = 1.0f;
      out.power = light.irradiance / (out.pdfLight * out.pdfPos);
      break;
    }
    case LightType::Area: {
      const Vec3 local = squareToCosineHemisphere(uDir);
      out.d = Frame(out.n).toWorld(local);
      out.pdfDir = squareToCosineHemispherePdf(local);
      if (!(out.pdfDir > 0.0f)) return false;
      out.power = out.radiance * (local.z / out.pdfDir);
      break;
    }
  }
  return maxComponent(out.power) > 0.0f;
}

}  // namespace firstshot
