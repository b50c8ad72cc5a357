#include "common/bsdf.h"

#include <algorithm>

#include "common/fresnel.h"
#include "common/sampling.h"
#include "common/scene_desc.h"

namespace fs {

namespace {
/// Marks a failed sample and returns a zero weight.
Color fail(BSDFQuery& q) {
  q.pdf = 0.0f;
  q.specular = false;
  q.eta = 1.0f;
  return Color(0.0f);
}

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
  if (q.wo.z == 0.0f) return fail(q);
  q.wi = cosineOnSideOf(q.wo, u);
  if (q.wi.z == 0.0f) return fail(q);  // rim of the disk: zero density, zero BSDF
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
  if (q.wo.z == 0.0f) return fail(q);
  if (u.x < pDiffuse) {
    const Vec2 v(std::min(u.x / pDiffuse, 0x1.fffffep-1f), u.y);
    q.wi = cosineOnSideOf(q.wo, v);
  } else {
    const Vec2 v(std::min((u.x - pDiffuse) / (1.0f - pDiffuse), 0x1.fffffep-1f), u.y);
    q.wi = glm::normalize(samplePhongLobe(reflectLocal(q.wo), n, v));
  }
  if (!sameSide(q)) return fail(q);  // lobe sample below the horizon (or on it)
  q.pdf = pdf(q);
  if (!(q.pdf > 0.0f)) return fail(q);
  q.specular = false;
  q.eta = 1.0f;
  return eval(q) * (std::abs(q.wi.z) / q.pdf);
}

// ---- Mirror ----

Color MirrorBRDF::sample(BSDFQuery& q, const Vec2&) const {
  if (q.wo.z == 0.0f) return fail(q);
  q.wi = reflectLocal(q.wo);
  q.pdf = 1.0f;
  q.specular = true;
  q.eta = 1.0f;
  return tint;
}

// ---- Dielectric ----

Color DielectricBSDF::sample(BSDFQuery& q, const Vec2& u) const {
  if (q.wo.z == 0.0f) return fail(q);
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

// ---- BSDF ----

Color BSDF::diffuseAlbedo() const {
  if (const auto* l = std::get_if<LambertBRDF>(&model_)) return l->rho;
  if (const auto* p = std::get_if<StretchedPhongBRDF>(&model_)) return p->rhoD;
  return Color(0.0f);
}

BSDF makeBSDF(const MaterialDesc& m) { return makeBSDF(m, m.albedo); }

BSDF makeBSDF(const MaterialDesc& m, const Color& albedo) {
  switch (m.type) {
    case MaterialType::Diffuse: return LambertBRDF{albedo};
    // The scene's "specular" is the lobe's energy bound: ks·2π/(n+1) ≥ its directional albedo at every
    // incidence angle, so albedo + specular ≤ 1 (checked by validateScene) conserves energy.
    case MaterialType::Glossy:
      return StretchedPhongBRDF(albedo, m.specular * StretchedPhongBRDF::glossyEnergyBound(m.exponent), m.exponent);
    case MaterialType::Mirror: return MirrorBRDF{m.specular};
    case MaterialType::Dielectric: return DielectricBSDF{m.ior, m.transmittance};
  }
  return LambertBRDF{albedo};
}

}  // namespace fs
