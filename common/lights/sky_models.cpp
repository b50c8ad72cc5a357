#include "common/lights/sky_models.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

namespace {

/// Kittler's gradation φ(θ) = 1 − exp(−0.32 / cos θ) for cos θ > 0.
double gradation(double cosTheta) { return 1.0 - std::exp(-0.32 / cosTheta); }

/// Kittler's indicatrix f(γ) = 0.91 + 10 exp(−3γ) + 0.45 cos²γ, γ in radians.
double indicatrix(double gamma) {
  const double c = std::cos(gamma);
  return 0.91 + 10.0 * std::exp(-3.0 * gamma) + 0.45 * c * c;
}

/// Perez's lv(ζ, γ) = [1 + a exp(b / cos ζ)] · [1 + c exp(d γ) + e cos² γ] for cos ζ > 0.
double perezRelative(const double (&p)[5], double cosZeta, double gamma) {
  const double c = std::cos(gamma);
  return (1.0 + p[0] * std::exp(p[1] / cosZeta)) * (1.0 + p[2] * std::exp(p[3] * gamma) + p[4] * c * c);
}

}  // namespace

double SkyLuminance::relative(const Vec3d& dir) const {
  const double cosTheta = dir.y;
  if (type_ == SkyType::CieOvercast) return (1.0 + 2.0 * cosTheta) / 3.0;
  const double gamma = std::acos(std::clamp(glm::dot(dir, sun_), -1.0, 1.0));
  if (type_ == SkyType::CieClear) return gradation(cosTheta) * indicatrix(gamma) * clearNorm_;
  return std::max(perezRelative(perez_, cosTheta, gamma) * clearNorm_, 0.0);
}

double SkyLuminance::luminance(const Vec3d& dir) const { return dir.y > 0.0 ? zenith_ * relative(dir) : 0.0; }

void preethamCoefficients(double turbidity, double (&abcde)[5]) {
  const double t = std::clamp(turbidity, 2.0, 10.0);
  abcde[0] = 0.1787 * t - 1.4630, abcde[1] = -0.3554 * t + 0.4275, abcde[2] = -0.0227 * t + 5.3251;
  abcde[3] = 0.1206 * t - 2.5771, abcde[4] = -0.0670 * t + 0.3703;
}

double relativeHorizontalIntegral(const SkyLuminance& sky) {
  if (sky.type() == SkyType::CieOvercast) return 7.0 * kPi / 9.0;
  // Midpoint rule in (μ = cos θ, azimuth): dω = dμ dφ, integrand relative · μ.
  constexpr int kMu = 512, kPhi = 1024;
  double sum = 0.0;
  for (int i = 0; i < kMu; ++i) {
    const double mu = (i + 0.5) / kMu, s = std::sqrt(1.0 - mu * mu);
    double ring = 0.0;
    for (int j = 0; j < kPhi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / kPhi;
      ring += sky.relative(Vec3d(s * std::cos(phi), mu, s * std::sin(phi)));
    }
    sum += ring * mu;
  }
  return sum * (1.0 / kMu) * (2.0 * kPi / kPhi);
}

SkyLuminance SkyLuminance::overcast(double horizontalLux) {
  SkyLuminance s;
  s.type_ = SkyType::CieOvercast;
  s.horizontal_ = horizontalLux;
  s.zenith_ = horizontalLux / relativeHorizontalIntegral(s);
  return s;
}

SkyLuminance SkyLuminance::clear(const Vec3d& sunDir, double horizontalLux) {
  SkyLuminance s;
  s.type_ = SkyType::CieClear;
  s.sun_ = glm::normalize(sunDir);
  const double sunZenith = std::acos(std::clamp(s.sun_.y, -1.0, 1.0));
  s.clearNorm_ = 1.0 / (gradation(1.0) * indicatrix(sunZenith));
  s.horizontal_ = horizontalLux;
  s.zenith_ = horizontalLux / relativeHorizontalIntegral(s);
  return s;
}

SkyLuminance SkyLuminance::perez(const Vec3d& sunDir, const double (&abcde)[5], double horizontalLux) {
  SkyLuminance s;
  s.type_ = SkyType::Perez;
  s.sun_ = glm::normalize(sunDir);
  std::copy(abcde, abcde + 5, s.perez_);
  const double sunZenith = std::acos(std::clamp(s.sun_.y, -1.0, 1.0));
  s.clearNorm_ = 1.0 / perezRelative(s.perez_, 1.0, sunZenith);
  s.horizontal_ = horizontalLux;
  s.zenith_ = horizontalLux / relativeHorizontalIntegral(s);
  return s;
}

}  // namespace firstshot
