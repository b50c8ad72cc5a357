// A thin glass pane's reflectance and transmittance (thin_glass.h) and its two delta lobes.
#include "common/materials/thin_glass.h"

#include <algorithm>
#include <cmath>

#include "common/materials/bsdf_query.h"
#include "common/materials/fresnel.h"

namespace firstshot {

namespace {

float channelMean(const Color& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

/// One pane, one polarisation: interface reflectance @p r, one pass's transmittance @p a.
void paneSums(float r, const Color& a, Color& R, Color& T) {
  const Color ra = r * a;
  const Color denom = Color(1.0f) - ra * ra;
  T += (1.0f - r) * (1.0f - r) * a / denom;
  R += r + r * (1.0f - r) * (1.0f - r) * a * a / denom;
}

}  // namespace

float ThinGlassBSDF::maxTransmittance(float ior) {
  const float s = (ior - 1.0f) / (ior + 1.0f);
  const float r0 = s * s;
  return (1.0f - r0) / (1.0f + r0);
}

ThinGlassBSDF::ThinGlassBSDF(const Color& tau, float ior_) : ior(ior_) {
  const float s = (ior - 1.0f) / (ior + 1.0f);
  const float r0 = s * s, q = (1.0f - r0) * (1.0f - r0);
  const float tMax = maxTransmittance(ior);
  for (int c = 0; c < 3; ++c) {
    const float t = std::clamp(tau[c], 0.0f, tMax);
    if (t <= 0.0f) {
      a0[c] = 0.0f;
    } else if (r0 <= 0.0f) {
      a0[c] = t;
    } else {  // τ r0² a² + q a − τ = 0, the positive root written without cancellation
      a0[c] = std::min(1.0f, 2.0f * t / (q + std::sqrt(q * q + 4.0f * t * t * r0 * r0)));
    }
  }
}

void ThinGlassBSDF::reflectTransmit(float cosTheta, Color& R, Color& T) const {
  R = T = Color(0.0f);
  const float ci = std::clamp(cosTheta, 0.0f, 1.0f);
  if (!(ci > 0.0f)) {
    R = Color(1.0f);
    return;
  }
  const float sin2T = (1.0f - ci * ci) / (ior * ior);
  const float ct = std::sqrt(std::max(0.0f, 1.0f - sin2T));  // ior ≥ 1 from outside: no total reflection
  const float rs = (ci - ior * ct) / (ci + ior * ct), rp = (ior * ci - ct) / (ior * ci + ct);
  const float invCt = ct > 0.0f ? 1.0f / ct : 0.0f;
  const Color a(std::pow(a0.x, invCt), std::pow(a0.y, invCt), std::pow(a0.z, invCt));
  paneSums(rs * rs, a, R, T);
  paneSums(rp * rp, a, R, T);
  R *= 0.5f;
  T *= 0.5f;
}

Color ThinGlassBSDF::transmittance(float cosTheta) const {
  Color R, T;
  reflectTransmit(cosTheta, R, T);
  return T;
}

Color ThinGlassBSDF::reflectance(float cosTheta) const {
  Color R, T;
  reflectTransmit(cosTheta, R, T);
  return R;
}

float ThinGlassBSDF::transmitProbability(const Color& R, const Color& T) {
  const float t = channelMean(T), sum = t + channelMean(R);
  return sum > 0.0f ? t / sum : 0.0f;
}

Color ThinGlassBSDF::albedo() const {
  Color R, T;
  reflectTransmit(1.0f, R, T);
  return R + T;
}

Color ThinGlassBSDF::sample(BSDFQuery& q, const Vec2& u) const {
  q.specular = true;
  q.eta = 1.0f;
  if (q.wo.z == 0.0f) {
    q.pdf = 0.0f;
    q.specular = false;
    return Color(0.0f);
  }
  Color R, T;
  reflectTransmit(std::abs(q.wo.z), R, T);
  const float pT = transmitProbability(R, T);
  if (u.x < pT) {
    q.wi = -q.wo;
    q.pdf = pT;
    return T / pT;
  }
  q.wi = reflectLocal(q.wo);
  q.pdf = 1.0f - pT;
  return q.pdf > 0.0f ? R / q.pdf : Color(0.0f);
}

}  // namespace firstshot
