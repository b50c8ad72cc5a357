// The image errors of the speed-against-error harness (bench/image_metrics.h, firstshot-compare):
// exact values on small images, and the reference-noise estimate from two half references.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "bench/image_metrics.h"

using firstshot::bench::compareImages;
using firstshot::bench::meanImage;

TEST(BenchMetrics, UniformTenPercentError) {
  const std::vector<float> ref(300, 1.0f), test(300, 1.1f);
  const auto e = compareImages(test, ref);
  EXPECT_NEAR(e.epsilon, 0.01, 1e-9);
  EXPECT_NEAR(e.relRmse, 0.1 / 1.01, 1e-6);
  EXPECT_NEAR(e.mare, 0.1 / 1.01, 1e-6);
  EXPECT_NEAR(e.rmse, 0.1, 1e-6);
  EXPECT_NEAR(e.nrmse, 0.1, 1e-6);
  EXPECT_EQ(e.values, 300u);
}

TEST(BenchMetrics, MixedValuesByHand) {
  // ref mean 2, ε = 0.02: relative errors 1/1.02 and 0.
  const std::vector<float> ref = {1, 3}, test = {2, 3};
  const auto e = compareImages(test, ref);
  EXPECT_NEAR(e.relRmse, std::sqrt(0.5) / 1.02, 1e-9);
  EXPECT_NEAR(e.mare, 0.5 / 1.02, 1e-9);
  EXPECT_NEAR(e.rmse, std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(e.nrmse, std::sqrt(0.5) / 2, 1e-9);
  // ε scales with the fraction; 0 gives plain relative errors.
  EXPECT_NEAR(compareImages(test, ref, 0.0).mare, 0.5, 1e-9);
}

TEST(BenchMetrics, NonFiniteValuesAreCountedAndSkipped) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<float> ref = {1, 1, 1, 1}, test = {1.5f, nan, inf, 1.5f};
  const auto e = compareImages(test, ref);
  EXPECT_EQ(e.nonFinite, 2u);
  EXPECT_EQ(e.values, 2u);
  EXPECT_NEAR(e.mare, 0.5 / 1.01, 1e-6);
}

TEST(BenchMetrics, SizeMismatchThrows) {
  const std::vector<float> a(3, 1.0f), b(6, 1.0f);
  EXPECT_THROW(compareImages(a, b), std::invalid_argument);
  EXPECT_THROW(meanImage(a, b), std::invalid_argument);
}

// The harness estimates a reference's own error as the error of half A against the mean of halves A
// and B: A - (A+B)/2 = (A-B)/2 has the distribution of (A+B)/2 - truth for independent halves. With
// Gaussian noise the two relative RMSEs agree within their sampling error, up to the estimate's
// second-order bias: it divides by the noisy mean M instead of the truth T, and E[T²/M²] ≈ 1 + 3s²
// (s = σ_M/T) makes it larger by ≈ 1.5s² in relative terms (0.75% here at s = 7%, 0.1% at s = 3%).
TEST(BenchMetrics, HalfReferenceEstimatesTheMeansError) {
  const size_t n = 300000;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> level(0.2f, 2.0f);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  std::vector<float> truth(n), a(n), b(n);
  for (size_t k = 0; k < n; ++k) {
    truth[k] = level(rng);
    const float sigma = 0.1f * truth[k];  // 10% relative noise per half
    a[k] = truth[k] + sigma * noise(rng);
    b[k] = truth[k] + sigma * noise(rng);
  }
  const std::vector<float> mean = meanImage(a, b);
  const double estimate = compareImages(a, mean).relRmse;
  const double actual = compareImages(mean, truth).relRmse;
  // Each is the root of a mean of n i.i.d. squares: relative standard error ≈ √(Var(x²)/n)/(2 E[x²])
  // ≤ 1/√(2n) for Gaussian x (ε only shrinks the spread); the difference of two is within 4√2 of that.
  const double tolerance = 4 * std::sqrt(2.0) / std::sqrt(2.0 * n);
  const double s = 0.1 / std::sqrt(2.0);
  EXPECT_NEAR(estimate / actual, 1.0 + 1.5 * s * s, tolerance);
  // And both are close to the mean's true relative noise, 0.1/√2 (up to ε ≈ 1% of the mean level).
  EXPECT_NEAR(actual, s, 0.03 * s);
}
