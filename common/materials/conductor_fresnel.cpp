// The Fresnel reflectance of a conductor (conductor_fresnel.h).
#include "common/materials/conductor_fresnel.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

float fresnelConductor(float cosThetaI, float eta, float k) {
  const float c = std::clamp(cosThetaI, 0.0f, 1.0f);
  const float s2 = 1.0f - c * c;
  // n² = nr + i·ni; w² = n² − sin²θ = t + i·ni. Re w = a, Im w = b, from |w²| and a·b = ni/2: the larger of the
  // two by its square root, the smaller by the product, so that neither loses digits to cancellation.
  const float nr = eta * eta - k * k, ni = 2.0f * eta * k;
  const float t = nr - s2;
  const float modulus = std::hypot(t, ni);
  float a = 0.0f, b = 0.0f;
  if (t >= 0.0f) {
    a = std::sqrt(0.5f * (modulus + t));
    b = a > 0.0f ? 0.5f * ni / a : 0.0f;
  } else {
    b = std::sqrt(0.5f * (modulus - t));
    a = 0.5f * ni / b;
  }
  // |r_s|² = |c − w|²/|c + w|², |r_p|² = |n² c − w|²/|n² c + w|². A zero denominator is the grazing limit of an
  // interface without contrast (c = 0, w = 0), where F → 1.
  const float sDen = (c + a) * (c + a) + b * b;
  const float pDen = (nr * c + a) * (nr * c + a) + (ni * c + b) * (ni * c + b);
  if (!(sDen > 0.0f) || !(pDen > 0.0f)) return 1.0f;
  const float rs = ((c - a) * (c - a) + b * b) / sDen;
  const float rp = ((nr * c - a) * (nr * c - a) + (ni * c - b) * (ni * c - b)) / pDen;
  return std::min(1.0f, 0.5f * (rs + rp));
}

ConductorFresnel::ConductorFresnel(const Color& eta, const Color& k) : eta_(eta), k_(k) {
  // ∫₀¹ F(c)·2c dc by Simpson's rule in c, summed in double: F is smooth for k > 0 (within 1e-6 of the limit, float
  // rounding aside); k = 0 with η < 1 has a kink at the critical angle (within 1e-4 there: 7e-5 at η = 1/1.5).
  constexpr int kIntervals = 1024;
  for (int ch = 0; ch < 3; ++ch) {
    double sum = 0.0;
    for (int i = 0; i <= kIntervals; ++i) {
      const double c = double(i) / kIntervals;
      const double w = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += w * 2.0 * c * fresnelConductor(float(c), eta_[ch], k_[ch]);
    }
    mean_[ch] = float(sum / (3.0 * kIntervals));
  }
}

Color ConductorFresnel::normalIncidence() const {
  const Color num = (eta_ - 1.0f) * (eta_ - 1.0f) + k_ * k_;
  const Color den = (eta_ + 1.0f) * (eta_ + 1.0f) + k_ * k_;
  return num / den;
}

}  // namespace firstshot
