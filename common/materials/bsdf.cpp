#include "common/materials/bsdf.h"

#include <algorithm>

#include "common/materials/fresnel.h"
#include "common/materials/microfacet.h"
#include "common/sampling/sampling.h"
#include "common/scene/scene_desc.h"

namespace firstshot {

namespace {

float mean(const Color& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

/// True if wi and wo lie strictly on the same side of the surface.
bool sameSide(const BSDFQuery& q) { return q.wi.z * q.wo.z > 0.0f; }

/// Cosine-weighted direction on the side of wo.
Vec3 cosineOnSideOf(const Vec3& wo, const Vec2& u) {
  Vec3 w = squareToCosineHemisphere(u);
  if (wo.z < 0.0f) w.z = -w.z;
  return w;
}
}  // namespace

// ---- Lambert ----

Color LambertBRDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  q.wi = cosineOnSideOf(q.wo, u);
  if (q.wi.z == 0.0f) return failedSample(q);  // rim of the disk: zero density, zero BSDF
  q.pdf = std::abs(q.wi.z) * kInvPiF;
  q.specular = false;
  q.eta = 1.0f;
  return rho;  // (ρ/π)·cos / (cos/π)
}

Color LambertBRDF::eval(const BSDFQuery& q) const { return sameSide(q) ? rho * kInvPiF : Color(0.0f); }

float LambertBRDF::pdf(const BSDFQuery& q) const { return sameSide(q) ? std::abs(q.wi.z) * kInvPiF : 0.0f; }

// ---- Stretched Phong ----

StretchedPhongBRDF::StretchedPhongBRDF(const Color& rhoD_, const Color& ks_, float n_)
    : rhoD(rhoD_), ks(ks_), n(n_) {
  const float wd = std::max(0.0f, mean(rhoD));
  const float ws = std::max(0.0f, mean(ks)) * 2.0f * kPiF / (n + 2.0f);
  pDiffuse = (wd + ws > 0.0f) ? wd / (wd + ws) : 1.0f;
}

Color StretchedPhongBRDF::eval(const BSDFQuery& q) const {
  if (!sameSide(q)) return Color(0.0f);
  const float cosI = std::abs(q.wi.z), cosO = std::abs(q.wo.z);
  const float cosPsi = std::min(1.0f, glm::dot(q.wi, reflectLocal(q.wo)));
  Color f = rhoD * kInvPiF;
  if (cosPsi > 0.0f) f += ks * (std::pow(cosPsi, n) / std::max(cosI, cosO));
  return f;
}

float StretchedPhongBRDF::pdf(const BSDFQuery& q) const {
  if (!sameSide(q)) return 0.0f;
  const float cosPsi = std::min(1.0f, glm::dot(q.wi, reflectLocal(q.wo)));
  return pDiffuse * std::abs(q.wi.z) * kInvPiF + (1.0f - pDiffuse) * squareToPhongLobePdf(cosPsi, n);
}

Color StretchedPhongBRDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  if (u.x < pDiffuse) {
    const Vec2 v(std::min(u.x / pDiffuse, 0x1.fffffep-1f), u.y);
    q.wi = cosineOnSideOf(q.wo, v);
  } else {
    const Vec2 v(std::min((u.x - pDiffuse) / (1.0f - pDiffuse), 0x1.fffffep-1f), u.y);
    q.wi = glm::normalize(samplePhongLobe(reflectLocal(q.wo), n, v));
  }
  if (!sameSide(q)) return failedSample(q);  // lobe sample below the horizon (or on it)
  q.pdf = pdf(q);
  if (!(q.pdf > 0.0f)) return failedSample(q);
  q.specular = false;
  q.eta = 1.0f;
  return eval(q) * (std::abs(q.wi.z) / q.pdf);
}

// ---- Mirror ----

Color MirrorBRDF::sample(BSDFQuery& q, const Vec2&) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  q.wi = reflectLocal(q.wo);
  q.pdf = 1.0f;
  q.specular = true;
  q.eta = 1.0f;
  return fresnel ? tint * fresnel->eval(std::abs(q.wo.z)) : tint;
}

// ---- Dielectric ----

Color DielectricBSDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  const bool outside = q.wo.z > 0.0f;
  const float eta = outside ? ior : 1.0f / ior;  // η(other side) / η(wo side)
  float cosT = 0.0f;
  const float R = fresnelDielectric(std::abs(q.wo.z), eta, &cosT);
  q.specular = true;
  if (u.x < R) {
    q.wi = reflectLocal(q.wo);
    q.pdf = R;
    q.eta = 1.0f;
    return Color(1.0f);  // R / R
  }
  q.wi = refractLocal(q.wo, eta, cosT);
  q.pdf = 1.0f - R;
  q.eta = eta;
  const float scale = q.mode == TransportMode::Radiance ? 1.0f / (eta * eta) : 1.0f;
  return transmittance * scale;  // (1−R)·T·scale / (1−R)
}

// ---- Metallic-roughness (glTF) ----

namespace {
/// The local frame mirrored so that wo.z > 0 (the model is two-sided).
Vec3 upper(const Vec3& w, bool flip) { return flip ? Vec3(w.x, w.y, -w.z) : w; }
float dielectricF0(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}
/// The cosine-weighted hemispherical mean of Schlick's Fresnel: ∫ F(c) 2c dc = F0 + (1 − F0)/21.
float fresnelMean(float f0) { return f0 + (1.0f - f0) / 21.0f; }
}  // namespace

float MetallicRoughnessBRDF::pSpecular(float cosO) const {
  const float fd = schlickFresnel(Color(dielectricF0(ior)), cosO).x;
  const float ws = metallic * mean(metalFresnel(cosO)) + (1.0f - metallic) * fd;
  const float wd = (1.0f - metallic) * (1.0f - fd) * mean(baseColor);
  if (!(wd > 0.0f)) return 1.0f;
  return std::clamp(ws / (ws + wd), 0.02f, 0.98f);
}

Color MetallicRoughnessBRDF::eval(const BSDFQuery& q) const {
  if (!sameSide(q)) return Color(0.0f);
  const bool flip = q.wo.z < 0.0f;
  const Vec3 wi = upper(q.wi, flip), wo = upper(q.wo, flip);
  const float alpha = ggxAlpha(roughness);
  const float c = std::clamp(glm::dot(wo, glm::normalize(wi + wo)), 0.0f, 1.0f);
  const float s = microfacetSpecular(microfacet, wi, wo, alpha);
  const float f0 = dielectricF0(ior);
  const float fd = schlickFresnel(Color(f0), c).x;
  const float fi = schlickFresnel(Color(f0), wi.z).x, fo = schlickFresnel(Color(f0), wo.z).x;
  const float diffuse = (1.0f - fi) * (1.0f - fo) / (1.0f - fresnelMean(f0));
  const Color dielectric = baseColor * (diffuse * kInvPiF) + Color(fd * s);
  const Color metal = metalFresnel(c) * s;
  return metal * metallic + dielectric * (1.0f - metallic);
}

float MetallicRoughnessBRDF::pdf(const BSDFQuery& q) const {
  if (!sameSide(q)) return 0.0f;
  const bool flip = q.wo.z < 0.0f;
  const Vec3 wi = upper(q.wi, flip), wo = upper(q.wo, flip);
  const float ps = pSpecular(wo.z);
  return ps * microfacetReflectionPdf(microfacet, wi, wo, ggxAlpha(roughness)) + (1.0f - ps) * wi.z * kInvPiF;
}

Color MetallicRoughnessBRDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return failedSample(q);
  const bool flip = q.wo.z < 0.0f;
  const Vec3 wo = upper(q.wo, flip);
  const float ps = pSpecular(wo.z);
  Vec3 wi;
  if (u.x < ps) {
    const Vec2 v(std::min(u.x / ps, 0x1.fffffep-1f), u.y);
    const Vec3 h = sampleMicrofacetNormal(microfacet, wo, ggxAlpha(roughness), v);
    // Beckmann's normals are drawn without regard to wo: one facing away from it reflects nothing (the density
    // pdf() gives counts only facets that face wo). GGX's visible normals always face wo.
    if (microfacet == MicrofacetModel::Beckmann && !(glm::dot(wo, h) > 0.0f)) return failedSample(q);
    wi = 2.0f * glm::dot(wo, h) * h - wo;
  } else {
    wi = squareToCosineHemisphere(Vec2(std::min((u.x - ps) / (1.0f - ps), 0x1.fffffep-1f), u.y));
  }
  if (!(wi.z > 0.0f)) return failedSample(q);  // a microfacet reflection below the horizon (or the disk's rim)
  q.wi = upper(glm::normalize(wi), flip);
  q.pdf = pdf(q);
  if (!(q.pdf > 0.0f)) return failedSample(q);
  q.specular = false;
  q.eta = 1.0f;
  return eval(q) * (std::abs(q.wi.z) / q.pdf);
}

Color MetallicRoughnessBRDF::albedo() const {
  const float f0 = dielectricF0(ior);
  const float fd = fresnelMean(f0);
  const Color metal =
      conductor ? baseColor * conductor->hemisphericalMean() : baseColor + (Color(1.0f) - baseColor) * (1.0f / 21.0f);
  return metal * metallic + (Color(fd) + baseColor * (1.0f - fd)) * (1.0f - metallic);
}

// ---- BSDF ----

Color BSDF::diffuseAlbedo() const {
  if (shaded_) return Color(0.0f);  // shaded: no Lambertian part about the geometric normal
  if (const auto* l = std::get_if<LambertBRDF>(&model_)) return l->rho;
  if (const auto* p = std::get_if<StretchedPhongBRDF>(&model_)) return p->rhoD;
  return Color(0.0f);
}

BSDF makeBSDF(const MaterialDesc& m) { return makeBSDF(m, m.albedo); }

BSDF makeBSDF(const MaterialDesc& m, const Color& albedo, float metallic, float roughness) {
  if (m.type == MaterialType::Pbr)
    return MetallicRoughnessBRDF{albedo, metallic, roughness, m.ior, m.microfacet, m.conductor};
  return makeBSDF(m, albedo);
}

BSDF makeBSDF(const MaterialDesc& m, const Color& albedo) {
  switch (m.type) {
    case MaterialType::Diffuse: return LambertBRDF{albedo};
    // The scene's "specular" is the lobe's energy bound: ks·2π/(n+1) ≥ its directional albedo at every
    // incidence angle, so albedo + specular ≤ 1 (checked by validateScene) conserves energy.
    case MaterialType::Glossy:
      return StretchedPhongBRDF(albedo, m.specular * StretchedPhongBRDF::glossyEnergyBound(m.exponent), m.exponent);
    case MaterialType::Mirror: return MirrorBRDF{m.specular, m.conductor};
    case MaterialType::Dielectric:
      if (m.glassRoughness > 0.0f) return RoughDielectricBSDF{m.ior, m.transmittance, m.glassRoughness};
      return DielectricBSDF{m.ior, m.transmittance};
    case MaterialType::Pbr:
      return MetallicRoughnessBRDF{albedo, m.metallic, m.roughness, m.ior, m.microfacet, m.conductor};
    case MaterialType::ThinGlass:
      if (m.glassRoughness > 0.0f) return RoughThinGlassBSDF{ThinGlassBSDF(m.transmittance, m.ior), m.glassRoughness};
      return ThinGlassBSDF(m.transmittance, m.ior);
  }
  return LambertBRDF{albedo};
}

}  // namespace firstshot
