// Albedos and lobe widths of Mitsuba 0.6's roughdiffuse, ward and phong (common/formats/mitsuba/mitsuba_lobes.h).
#include "common/formats/mitsuba/mitsuba_lobes.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/util/math.h"

namespace firstshot::mitsuba {
namespace {

/// Mitsuba's Oren–Nayar BRDF times π for reflectance ρ, as single + twice·ρ (each to be multiplied by ρ), at
/// incidence and exitance angles of sines @p sinI, @p sinO and cos(φo − φi) = @p cosPhi.
std::pair<double, double> orenNayar(double sinI, double sinO, double cosPhi, double sigma2, bool fast) {
  const double cosI = std::sqrt(1 - sinI * sinI), cosO = std::sqrt(1 - sinO * sinO);
  // α is the larger polar angle, β the smaller; tan β from the direction nearer the normal.
  const bool inIsSteeper = cosI > cosO;
  const double sinAlpha = inIsSteeper ? sinO : sinI, sinBeta = inIsSteeper ? sinI : sinO;
  const double tanBeta = inIsSteeper ? sinI / cosI : sinO / cosO;
  if (fast) {
    const double a = 1 - 0.5 * sigma2 / (sigma2 + 0.33), b = 0.45 * sigma2 / (sigma2 + 0.09);
    return {a + b * std::max(cosPhi, 0.0) * sinAlpha * tanBeta, 0.0};
  }
  const double alpha = std::asin(sinAlpha), beta = std::asin(sinBeta);
  const double g = sigma2 / (sigma2 + 0.09), ab = 4 / (kPi * kPi) * alpha * beta, b2 = 2 * beta / kPi;
  const double c1 = 1 - 0.5 * sigma2 / (sigma2 + 0.33), c3 = 0.125 * g * ab * ab, c4 = 0.17 * sigma2 / (sigma2 + 0.13);
  const double c2 = 0.45 * g * (cosPhi > 0 ? sinAlpha : sinAlpha - b2 * b2 * b2);
  const double tanHalfSum = (sinAlpha + sinBeta) / (std::sqrt(1 - sinAlpha * sinAlpha) + std::sqrt(1 - sinBeta * sinBeta));
  return {c1 + cosPhi * c2 * tanBeta + (1 - std::abs(cosPhi)) * c3 * tanHalfSum, c4 * (1 - cosPhi * b2 * b2)};
}

}  // namespace

OrenNayarAlbedo orenNayarAlbedo(double alpha, bool fastApproximation) {
  // White-sky albedo = (1/π) ∫∫ f cosθi cosθo dωi dωo; with s = sin²θ, cosθ dω = ½ ds dφ, and f depending on
  // φo − φi alone (even in it): ∫₀^π d(φo − φi) ∫₀¹ dsi ∫₀¹ dso (π f).
  constexpr int kS = 48, kPhi = 64;
  const double sigma = alpha / std::sqrt(2.0), sigma2 = sigma * sigma;
  double single = 0, twice = 0;
  for (int i = 0; i < kS; ++i) {
    const double sinI = std::sqrt((i + 0.5) / kS);
    for (int o = 0; o < kS; ++o) {
      const double sinO = std::sqrt((o + 0.5) / kS);
      for (int p = 0; p < kPhi; ++p) {
        const auto [s, t] = orenNayar(sinI, sinO, std::cos(kPi * (p + 0.5) / kPhi), sigma2, fastApproximation);
        single += s, twice += t;
      }
    }
  }
  const double weight = (kPi / kPhi) / (double(kS) * kS) / kPi;  // the rule's cell, and f = (π f)/π
  return {single * weight, twice * weight};
}

double wardAlbedoAtNormalIncidence(double alpha, const char* variant) {
  // Light along the normal, leaving at θ in the plane y = 0: the unnormalised half vector is (sin θ, 0, 1 + cos θ),
  // so tan²θh = sin²θ/(1 + cos θ)². Albedo = 2π ∫₀^{π/2} f cos θ sin θ dθ.
  const std::string v = variant;
  constexpr int kSteps = 4000;
  double sum = 0;
  for (int k = 0; k < kSteps; ++k) {
    const double theta = (k + 0.5) / kSteps * kPi / 2, c = std::cos(theta), s = std::sin(theta);
    const double e = std::exp(-(s * s) / ((1 + c) * (1 + c)) / (alpha * alpha));
    double f = 0;
    if (v == "ward") f = e / (4 * kPi * alpha * alpha * std::sqrt(c));
    else if (v == "ward-duer") f = e / (4 * kPi * alpha * alpha * c);
    else f = (2 + 2 * c) / (kPi * alpha * alpha * std::pow(1 + c, 4)) * e;  // balanced: H·H / (π α² H_z⁴)
    sum += f * c * s;
  }
  return 2 * kPi * sum * (kPi / 2) / kSteps;
}

double phongExponentOfRoughness(double alpha) { return std::max(0.0, (2 / (alpha * alpha) - 2) / 4); }

}  // namespace firstshot::mitsuba
