// The tabulated distribution (common/sampling/distribution_1d.h) against the hand-written CDFs it replaces: the discrete view
// picks the cell that a binary search over the whole CDF picks (the guide table only narrows the search, bucket edges
// included), its rest is u's position in the cell's interval, in [0, 1), probability() is the interval's width; a
// float table rounds as a float CDF summed in double; zero cells are never drawn and an all-zero table is uniform;
// the continuous density is each cell's value over the mean, the density of its own samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/sampling/distribution_1d.h"
#include "common/sampling/rng.h"

using namespace firstshot;

namespace {

/// Irregular weights with zeros (runs of them too) and a range of magnitudes.
std::vector<double> weights(size_t n) {
  std::vector<double> w(n);
  for (size_t i = 0; i < n; ++i)
    w[i] = (i % 7 == 3 || i % 11 == 5 || i % 23 >= 20) ? 0.0 : std::pow(1.7, double(i % 13)) * double(1 + i % 5);
  return w;
}

/// The CDF as the samplers wrote it by hand: partial sums in double, each stored in Real, divided by the total.
template <typename Real>
std::vector<Real> handCdf(const std::vector<double>& w) {
  std::vector<Real> cdf;
  double sum = 0;
  for (double x : w) cdf.push_back(Real(sum += x));
  for (Real& c : cdf) c = Real(double(c) / sum);
  cdf.back() = Real(1);
  return cdf;
}

/// Every u that could show a guide one bucket off, or a boundary taken on the wrong side, plus random ones.
template <typename Real>
std::vector<Real> probes(const std::vector<Real>& cdf) {
  const size_t n = cdf.size();
  std::vector<Real> us;
  for (size_t b = 0; b <= n; ++b) {
    const Real edge = Real(double(b) / double(n));
    us.insert(us.end(), {edge, std::nextafter(edge, Real(0)), std::nextafter(edge, Real(1))});
  }
  for (Real c : cdf) us.insert(us.end(), {c, std::nextafter(c, Real(0))});
  Sampler random(5, 0, 0, 0);
  for (int i = 0; i < 20000; ++i) us.push_back(Real(random.next1Dd()));
  for (Real& u : us) u = std::clamp(u, Real(0), std::nextafter(Real(1), Real(0)));
  return us;
}

template <typename Real>
void expectLikeHandWritten(size_t n) {
  const std::vector<double> w = weights(n);
  const PiecewiseConstant1D<Real> d(w);
  const std::vector<Real> cdf = handCdf<Real>(w);
  double total = 0;
  for (double x : w) total += x;
  EXPECT_EQ(d.total(), total);
  ASSERT_EQ(d.size(), n);
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(d.probability(i), cdf[i] - (i > 0 ? cdf[i - 1] : Real(0))) << i;
  for (Real u : probes(cdf)) {
    const size_t expected = std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()), n - 1);
    Real rest = -1;
    const size_t i = d.sampleDiscrete(u, &rest);
    ASSERT_EQ(i, expected) << "u = " << u;
    ASSERT_GT(w[i], 0.0) << "a zero cell drawn at u = " << u;
    const Real lo = i > 0 ? cdf[i - 1] : Real(0);
    EXPECT_EQ(rest, std::clamp((u - lo) / (cdf[i] - lo), Real(0), std::nextafter(Real(1), Real(0)))) << u;
  }
}

}  // namespace

TEST(Distribution1D, DiscreteChoiceIsTheWholeCdfsInversion) {
  for (size_t n : {1, 2, 3, 17, 1000, 4099}) {
    SCOPED_TRACE(n);
    expectLikeHandWritten<double>(n);
    expectLikeHandWritten<float>(n);
  }
}

TEST(Distribution1D, AllZeroIsUniformAndNegativesCountAsZero) {
  const Distribution1D zero(std::vector<double>(4, 0.0));
  EXPECT_EQ(zero.total(), 0.0);
  for (size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(zero.probability(i), 0.25);
  double rest = 0;
  EXPECT_EQ(zero.sampleDiscrete(0.6, &rest), 2u);
  EXPECT_NEAR(rest, 0.4, 1e-12);
  const Distribution1Df d({-2.0, 1.0, std::nan(""), 3.0});
  EXPECT_EQ(d.total(), 4.0);
  EXPECT_EQ(d.value(0), 0.0f);
  EXPECT_EQ(d.probability(0), 0.0f);
  EXPECT_EQ(d.probability(2), 0.0f);
  EXPECT_EQ(d.probability(3), 0.75f);
  EXPECT_EQ(d.sampleDiscrete(0.0f), 1u);
  EXPECT_EQ(d.sampleDiscrete(0.9f), 3u);
}

TEST(Distribution1D, ContinuousCellsAndZeros) {
  const Distribution1D d({1.0, 0.0, 3.0, 0.0});
  EXPECT_DOUBLE_EQ(d.integral(), 1.0);
  size_t cell = 9;
  double pdf = 0;
  for (double u : {0.0, 0.1, 0.249, 0.25, 0.6, 0.999}) {
    const double x = d.sample(u, cell, pdf);
    EXPECT_TRUE(cell == 0 || cell == 2) << u;  // zero cells are never drawn
    EXPECT_EQ(size_t(x * 4), cell);
    EXPECT_DOUBLE_EQ(pdf, d.pdf(x));
    EXPECT_DOUBLE_EQ(pdf, cell == 0 ? 1.0 : 3.0);
  }
  const Distribution1D zero({0.0, 0.0});
  EXPECT_DOUBLE_EQ(zero.pdf(0.3), 1.0);  // all zero: uniform
}
