#pragma once
/// @file bsdf_checks.h
/// Checks shared by the BSDF tests (test_bsdf.cpp, test_microfacet.cpp): directions from angles, a relative
/// comparison, the chi-square test of sample() against pdf() and the eval/pdf/sample consistency check.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/materials/bsdf.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "tests/direction_histogram.h"
#include "tests/stats.h"

namespace firstshot::test {

/// The fixed seed of the checks below.
inline constexpr uint64_t kBsdfCheckSeed = 777;

inline Vec3 dirFromAngles(float thetaDeg, float phiDeg) {
  const float t = thetaDeg * kPiF / 180.0f, p = phiDeg * kPiF / 180.0f;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

inline bool nearRel(float a, float b, float tol = 1e-4f) { return std::abs(a - b) <= tol * std::max(1.0f, std::abs(b)); }

/// Chi-square test of the directions drawn by bsdf.sample() for @p wo against bsdf.pdf() (conditioned
/// on success), and a binomial check that the success rate equals ∫pdf dω (3σ plus 2e-3 for the
/// quadrature). @p frame and @p zMin zoom the histogram onto a narrow lobe.
inline ChiSquareResult bsdfChiSquare(const BSDF& bsdf, const Vec3& wo, const Frame& frame = Frame(),
                                     double zMin = -1.0, int samples = 300000) {
  SphereHistogram h(24, 48, frame, zMin);
  Sampler rng(kBsdfCheckSeed, 1, 0);
  for (int i = 0; i < samples; ++i) {
    BSDFQuery q(wo);
    if (maxComponent(bsdf.sample(q, rng.next2D())) > 0.0f) h.add(q.wi);
  }
  double integral = 0.0;
  const auto exp = h.expected([&](const Vec3& wi) { return double(bsdf.pdf(BSDFQuery(wi, wo))); }, 8, &integral);
  const double rate = h.total() / samples;
  EXPECT_NEAR(rate, integral, 3 * std::sqrt(integral * (1 - integral) / samples) + 2e-3);
  const auto r = chiSquareTest(h.counts(), exp);
  std::printf("chi-square: %8.1f, dof %3d, p = %.4f; success rate %.4f, integral of pdf %.4f\n", r.statistic, r.dof,
              r.pValue, rate, integral);
  return r;
}

/// Checks on random (wo, u): weight = eval·|cos|/pdf, q.pdf = pdf(q), wi on the side of wo, unit.
inline void checkSampleConsistency(const BSDF& bsdf, int count = 20000) {
  Sampler rng(kBsdfCheckSeed, 2, 0);
  int ok = 0;
  for (int i = 0; i < count; ++i) {
    Vec3 wo = squareToUniformSphere(rng.next2D());
    BSDFQuery q(wo);
    const Color w = bsdf.sample(q, rng.next2D());
    if (maxComponent(w) <= 0.0f) {
      ASSERT_EQ(q.pdf, 0.0f);
      continue;
    }
    ++ok;
    ASSERT_NEAR(glm::length(q.wi), 1.0f, 1e-5f);
    ASSERT_GT(q.wi.z * q.wo.z, 0.0f);
    ASSERT_FALSE(q.specular);
    const float pdf = bsdf.pdf(q);
    const Color f = bsdf.eval(q);
    ASSERT_TRUE(nearRel(q.pdf, pdf)) << q.pdf << " vs " << pdf;
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(nearRel(w[c], f[c] * std::abs(q.wi.z) / pdf)) << w[c];
  }
  EXPECT_GT(ok, count / 2);
}

}  // namespace firstshot::test
