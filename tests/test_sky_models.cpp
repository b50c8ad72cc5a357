// Sky luminance models (common/sky_models.h): the horizontal illuminance each sky was scaled to, checked by an
// independent Monte Carlo integral (cosine-weighted directions, E = π · mean L, bound 4σ from the samples), the
// overcast sky's closed form 7π/9 · Lz and its zenith-to-horizon ratio 3, the clear sky's normalisation (relative 1
// at the zenith), symmetry about the sun's vertical plane, brightest towards the sun and darkest about 90° from it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/rng.h"
#include "common/sampling.h"
#include "common/sky_models.h"

using namespace fs;

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
