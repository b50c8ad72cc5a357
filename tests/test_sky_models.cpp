// Sky luminance models (common/lights/sky_models.h): the horizontal illuminance each sky was scaled to, checked by an
// independent Monte Carlo integral (cosine-weighted directions, E = π · mean L, bound 4σ from the samples), the
// overcast sky's closed form 7π/9 · Lz and its zenith-to-horizon ratio 3, the clear sky's normalisation (relative 1
// at the zenith), symmetry about the sun's vertical plane, brightest towards the sun and darkest about 90° from it.
// The Perez all-weather sky: its efficacies and parameters by hand, its dome against its horizontal illuminance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/lights/perez_sky.h"
#include "common/lights/sky_models.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"

using namespace firstshot;

namespace {

/// Horizontal illuminance of @p sky by cosine-weighted Monte Carlo: (estimate, σ of the estimate).
std::pair<double, double> monteCarloHorizontal(const SkyLuminance& sky, int n) {
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    Sampler s(7, i, 0);
    const Vec3 w = squareToCosineHemisphere(s.next2D());  // z up in the local frame
    const double v = kPi * sky.luminance(Vec3d(w.x, w.z, w.y));
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n, var = (sum2 / n - mean * mean) / (n - 1);
  return {mean, std::sqrt(std::max(var, 0.0))};
}

}  // namespace

TEST(SkyModels, OvercastClosedFormAndGradation) {
  const SkyLuminance sky = SkyLuminance::overcast(10000.0);
  EXPECT_NEAR(sky.zenithLuminance(), 10000.0 * 9.0 / (7.0 * kPi), 1e-9);
  EXPECT_NEAR(sky.luminance(Vec3d(0, 1, 0)) / sky.luminance(glm::normalize(Vec3d(1, 1e-9, 0))), 3.0, 1e-6);
  EXPECT_EQ(sky.luminance(Vec3d(0, -1, 0)), 0.0);
  const auto [e, sigma] = monteCarloHorizontal(sky, 200000);
  EXPECT_NEAR(e, 10000.0, 4 * sigma) << "σ " << sigma;
}

TEST(SkyModels, ClearSkyHorizontalIlluminanceByMonteCarlo) {
  for (double altitudeDeg : {15.0, 40.0, 70.0}) {
    const double a = altitudeDeg * kPi / 180;
    const SkyLuminance sky = SkyLuminance::clear(Vec3d(0, std::sin(a), std::cos(a)), 20000.0);
    EXPECT_NEAR(sky.relative(Vec3d(0, 1, 0)), 1.0, 1e-12);
    EXPECT_NEAR(sky.luminance(Vec3d(0, 1, 0)), sky.zenithLuminance(), 1e-9);
    const auto [e, sigma] = monteCarloHorizontal(sky, 400000);
    EXPECT_NEAR(e, 20000.0, 4 * sigma) << "sun altitude " << altitudeDeg << "°, σ " << sigma;
  }
}

TEST(SkyModels, ClearSkyShape) {
  const double a = 30.0 * kPi / 180;
  const Vec3d sun(0, std::sin(a), std::cos(a));  // the sun towards +z
  const SkyLuminance sky = SkyLuminance::clear(sun, 20000.0);
  // Symmetric about the sun's vertical plane (x ↦ −x).
  const Vec3d p = glm::normalize(Vec3d(0.6, 0.5, 0.3)), q(-p.x, p.y, p.z);
  EXPECT_NEAR(sky.luminance(p), sky.luminance(q), 1e-9 * sky.luminance(p));
  // Brightest at the sun; in its vertical plane, the darkest point of the anti-sun side is ~90° from the sun.
  double brightest = 0, brightestGamma = 0, darkest = 1e30, darkestGamma = 0;
  for (int k = 1; k < 1800; ++k) {
    const double t = k * kPi / 1800;  // from the sun's horizon point over the zenith to the opposite horizon
    const Vec3d d(0, std::sin(t), std::cos(t));
    const double l = sky.luminance(d), gamma = std::acos(std::clamp(glm::dot(d, sun), -1.0, 1.0)) * 180 / kPi;
    if (l > brightest) brightest = l, brightestGamma = gamma;
    if (l < darkest) darkest = l, darkestGamma = gamma;
  }
  EXPECT_LT(brightestGamma, 0.2);
  EXPECT_NEAR(darkestGamma, 90.0, 20.0) << darkest;
}

TEST(SkyModels, PerezEfficacyAndParametersByHand) {
  // The last clearness bin at Z = 30°, Δ = 0.1, W = 2 cm: 152.23 + 0.35·2 − 45.27 cos 30° − 7.98 ln 0.1 = 132.10 lm/W.
  EXPECT_NEAR(perezDiffuseEfficacy(7.0, 0.1, kPi / 6, 2.0), 132.0987, 1e-3);
  // Direct, bin 6 (ε 2.8–4.5): 107.19 − 1.25·2 − 1.51 exp(5.73·π/6 − 5) − 26.73·0.3 lm/W.
  EXPECT_NEAR(perezDirectEfficacy(3.0, 0.3, kPi / 6, 2.0), 107.19 - 2.5 - 1.51 * std::exp(5.73 * kPi / 6 - 5) - 8.019,
              1e-9);
  EXPECT_EQ(perezClearnessBin(1.0), 0);
  EXPECT_EQ(perezClearnessBin(1.065), 1);
  EXPECT_EQ(perezClearnessBin(6.5), 7);
  EXPECT_NEAR(relativeAirMass(0.0), 1.0 / (1.0 + 0.15 * std::pow(93.885, -1.253)), 1e-12);
  // ε and Δ from irradiances: Z = 60°, Dh = 100, In = 600 W/m² on day 172.
  const double z = kPi / 3;
  const PerezSky p = makePerezSky(Vec3d(0, std::cos(z), std::sin(z)), {100.0, 600.0, 172, 2.0});
  const double k = 1.041 * z * z * z;
  EXPECT_NEAR(p.clearness, (7.0 + k) / (1.0 + k), 1e-9);
  const double g = 2 * kPi * 171 / 365, e0 = 1.00011 + 0.034221 * std::cos(g) + 0.00128 * std::sin(g) +
                                             0.000719 * std::cos(2 * g) + 0.000077 * std::sin(2 * g);
  EXPECT_NEAR(p.brightness, 100.0 * relativeAirMass(60.0) / (1367.0 * e0), 1e-9);
  EXPECT_NEAR(p.directNormalLux, 600.0 * p.directEfficacy, 1e-6);
}

TEST(SkyModels, PerezSkiesHaveTheirHorizontalIlluminanceAndShape) {
  const double z = 50.0 * kPi / 180;
  const Vec3d sun(0, std::cos(z), std::sin(z));
  for (const PerezInput in : {PerezInput{150.0, 0.0, 80, 2.0}, PerezInput{200.0, 300.0, 172, 2.0},
                              PerezInput{80.0, 850.0, 200, 1.5}}) {
    const PerezSky p = makePerezSky(sun, in);
    EXPECT_GT(p.diffuseEfficacy, 60.0);
    EXPECT_LT(p.diffuseEfficacy, 180.0);
    EXPECT_NEAR(p.dome.horizontalIlluminance(), in.diffuseHorizontal * p.diffuseEfficacy, 1e-9);
    const auto [e, sigma] = monteCarloHorizontal(p.dome, 400000);
    EXPECT_NEAR(e, p.dome.horizontalIlluminance(), 4 * sigma) << "ε " << p.clearness << ", σ " << sigma;
    EXPECT_NEAR(p.dome.relative(Vec3d(0, 1, 0)), 1.0, 1e-12);
    if (p.clearness > 6.2) {  // clear: the circumsolar region is the brightest part of the dome
      const Vec3d nearSun = glm::normalize(sun + Vec3d(0, 0.01, 0)), away = glm::normalize(Vec3d(0, 0.6, -0.8));
      EXPECT_GT(p.dome.luminance(nearSun), 5 * p.dome.luminance(away));
    }
  }
  EXPECT_THROW(makePerezSky(sun, {0.0, 100.0, 1, 2.0}), std::invalid_argument);
  EXPECT_THROW(makePerezSky(Vec3d(0, -0.1, 1), {100.0, 100.0, 1, 2.0}), std::invalid_argument);
  EXPECT_THROW(makePerezSky(sun, {100.0, 100.0, 367, 2.0}), std::invalid_argument);
}
