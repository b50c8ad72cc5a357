// Rough glass: a GGX dielectric interface and a rough thin pane (rough_dielectric.h).
#include "common/materials/rough_dielectric.h"

#include <algorithm>
#include <cmath>

#include "common/materials/bsdf_query.h"
#include "common/materials/fresnel.h"
#include "common/materials/microfacet.h"

namespace firstshot {

namespace {

/// @p w with z negated when @p flip (the frame mirrored so that wo.z > 0).
Vec3 roughGlassMirror(const Vec3& w, bool flip) { return flip ? Vec3(w.x, w.y, -w.z) : w; }

/// The refraction half vector of wo (z > 0, relative index 1) and wi (z < 0, relative index eta), facing wo's side;
/// false if the pair cannot be a refraction by a microfacet seen from both (wo·h > 0 > wi·h).
bool refractionHalfVector(const Vec3& wi, const Vec3& wo, float eta, Vec3& h) {
  Vec3 m = -(eta * wi + wo);
  const float len = glm::length(m);
  if (!(len > 0.0f)) return false;
  m /= len;
  if (m.z < 0.0f) m = -m;
  h = m;
  return glm::dot(wo, h) > 0.0f && glm::dot(wi, h) < 0.0f;
}

/// The visible-normal density of h seen from wo (wo.z > 0): G1(wo)·max(0, wo·h)·D(h)/wo.z.
float visibleNormalPdf(const Vec3& wo, const Vec3& h, float alpha) {
  return ggxG1(wo, alpha) * std::max(0.0f, glm::dot(wo, h)) * ggxD(h, alpha) / wo.z;
}

float meanOf3(const Color& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

}  // namespace

// ---- Rough dielectric ----

float RoughDielectricBSDF::reflectProbability(float cosO, float eta) {
  return std::clamp(fresnelDielectric(cosO, eta), 0.02f, 0.98f);
}

Color RoughDielectricBSDF::eval(const BSDFQuery& q) const {
  if (q.wo.z == 0.0f || q.wi.z == 0.0f) return Color(0.0f);
  const bool flip = q.wo.z < 0.0f;
  const float eta = flip ? 1.0f / ior : ior;
  const Vec3 wo = roughGlassMirror(q.wo, flip), wi = roughGlassMirror(q.wi, flip);
  const float alpha = ggxAlpha(roughness);
  if (wi.z > 0.0f) {
    const Vec3 h = glm::normalize(wi + wo);
    return Color(fresnelDielectric(glm::dot(wo, h), eta) * ggxSpecular(wi, wo, alpha));
  }
  Vec3 h;
  if (!refractionHalfVector(wi, wo, eta, h)) return Color(0.0f);
  const float cO = glm::dot(wo, h), cI = glm::dot(wi, h);
  const float F = fresnelDielectric(cO, eta);
  const float denom = eta * cI + cO;
  float f = (1.0f - F) * ggxD(h, alpha) * ggxG2(wi, wo, alpha) * std::abs(cI) * cO /
            (std::abs(wi.z) * wo.z * denom * denom);
  if (q.mode == TransportMode::Importance) f *= eta * eta;  // the adjoint: f(wo → wi)
  return transmittance * f;
}

float RoughDielectricBSDF::pdf(const BSDFQuery& q) const {
  if (q.wo.z == 0.0f || q.wi.z == 0.0f) return 0.0f;
  const bool flip = q.wo.z < 0.0f;
  const float eta = flip ? 1.0f / ior : ior;
  const Vec3 wo = roughGlassMirror(q.wo, flip), wi = roughGlassMirror(q.wi, flip);
  const float alpha = ggxAlpha(roughness);
  const float pR = reflectProbability(wo.z, eta);
  if (wi.z > 0.0f) return pR * ggxReflectionPdf(wi, wo, alpha);
  Vec3 h;
  if (!refractionHalfVector(wi, wo, eta, h)) return 0.0f;
  const float cI = glm::dot(wi, h), denom = eta * cI + glm::dot(wo, h);
  // dω_h/dω_i = η²|wi·h|/(η wi·h + wo·h)² (Walter et al. 2007, eq. 17).
  return (1.0f - pR) * visibleNormalPdf(wo, h, alpha) * eta * eta * std::abs(cI) / (denom * denom);
}

Color RoughDielectricBSDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  const bool flip = q.wo.z < 0.0f;
  const float eta = flip ? 1.0f / ior : ior;
  const Vec3 wo = roughGlassMirror(q.wo, flip);
  const float alpha = ggxAlpha(roughness);
  const float pR = reflectProbability(wo.z, eta);
  const bool reflect = u.x < pR;
  const Vec2 v(std::min(reflect ? u.x / pR : (u.x - pR) / (1.0f - pR), 0x1.fffffep-1f), u.y);
  const Vec3 h = sampleGgxVisibleNormal(wo, alpha, v);
  const float c = glm::dot(wo, h);
  Vec3 wi;
  if (reflect) {
    wi = 2.0f * c * h - wo;
    if (!(wi.z > 0.0f)) return failedSample(q);
  } else {
    const float cos2T = 1.0f - (1.0f - c * c) / (eta * eta);
    if (!(cos2T > 0.0f)) return failedSample(q);  // total internal reflection at this microfacet
    wi = -wo / eta + (c / eta - std::sqrt(cos2T)) * h;
    if (!(wi.z < 0.0f)) return failedSample(q);
  }
  q.wi = roughGlassMirror(glm::normalize(wi), flip);
  q.pdf = pdf(q);
  if (!(q.pdf > 0.0f)) return failedSample(q);
  q.specular = false;
  q.eta = reflect ? 1.0f : eta;
  return eval(q) * (std::abs(q.wi.z) / q.pdf);
}

// ---- Rough thin pane ----

float RoughThinGlassBSDF::transmitProbability(float cosO) const {
  Color R, T;
  pane.reflectTransmit(cosO, R, T);
  const float p = ThinGlassBSDF::transmitProbability(R, T);
  return meanOf3(T) > 0.0f && meanOf3(R) > 0.0f ? std::clamp(p, 0.02f, 0.98f) : p;
}

Color RoughThinGlassBSDF::eval(const BSDFQuery& q) const {
  if (q.wo.z == 0.0f || q.wi.z == 0.0f) return Color(0.0f);
  const Vec3 wo(q.wo.x, q.wo.y, std::abs(q.wo.z)), w(q.wi.x, q.wi.y, std::abs(q.wi.z));
  const float s = ggxSpecular(w, wo, ggxAlpha(roughness));
  if (!(s > 0.0f)) return Color(0.0f);
  Color R, T;
  pane.reflectTransmit(glm::dot(wo, glm::normalize(w + wo)), R, T);
  return (q.wi.z * q.wo.z > 0.0f ? R : T) * s;
}

float RoughThinGlassBSDF::pdf(const BSDFQuery& q) const {
  if (q.wo.z == 0.0f || q.wi.z == 0.0f) return 0.0f;
  const Vec3 wo(q.wo.x, q.wo.y, std::abs(q.wo.z)), w(q.wi.x, q.wi.y, std::abs(q.wi.z));
  const float pT = transmitProbability(wo.z);
  return (q.wi.z * q.wo.z > 0.0f ? 1.0f - pT : pT) * ggxReflectionPdf(w, wo, ggxAlpha(roughness));
}

Color RoughThinGlassBSDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  const bool flip = q.wo.z < 0.0f;
  const Vec3 wo = roughGlassMirror(q.wo, flip);
  const float pT = transmitProbability(wo.z);
  const bool transmit = u.x < pT;
  const Vec2 v(std::min(transmit ? u.x / pT : (u.x - pT) / (1.0f - pT), 0x1.fffffep-1f), u.y);
  const Vec3 h = sampleGgxVisibleNormal(wo, ggxAlpha(roughness), v);
  Vec3 wi = 2.0f * glm::dot(wo, h) * h - wo;
  if (!(wi.z > 0.0f)) return failedSample(q);
  wi = glm::normalize(wi);
  if (transmit) wi.z = -wi.z;
  q.wi = roughGlassMirror(wi, flip);
  q.pdf = pdf(q);
  if (!(q.pdf > 0.0f)) return failedSample(q);
  q.specular = false;
  q.eta = 1.0f;
  return eval(q) * (std::abs(q.wi.z) / q.pdf);
}

}  // namespace firstshot
