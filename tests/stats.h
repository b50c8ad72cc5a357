#pragma once
/// @file stats.h
/// Statistics for the tests: running mean/variance with standard error, Pearson correlation, and
/// Pearson's chi-square goodness-of-fit test with an exact p-value (regularised upper incomplete
/// gamma function), in the manner of Nori's warptest.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <vector>

namespace firstshot::test {

/// Welford's running mean and variance.
struct RunningStats {
  size_t n = 0;
  double mean = 0.0, m2 = 0.0;
  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (x - mean);
  }
  /// Unbiased sample variance.
  double variance() const { return n > 1 ? m2 / static_cast<double>(n - 1) : 0.0; }
  /// Standard error of the mean.
  double standardError() const { return n > 0 ? std::sqrt(variance() / static_cast<double>(n)) : 0.0; }
};

/// Pearson correlation coefficient of two equally long series. Under independence it is
/// approximately normal with standard deviation 1/√n.
inline double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::min(a.size(), b.size());
  double ma = 0, mb = 0;
  for (size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
  ma /= static_cast<double>(n);
  mb /= static_cast<double>(n);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

/// Regularised upper incomplete gamma function Q(a, x) = Γ(a, x)/Γ(a): the series for x < a+1,
/// otherwise the continued fraction (modified Lentz). Accurate to ~1e-12 relative.
inline double gammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double lnPre = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int i = 0; i < 100000; ++i) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(lnPre));
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(lnPre) * h;
}

/// Šidák-corrected significance level: the per-test level that keeps the probability of at least one
/// false rejection among @p tests independent tests at @p familyAlpha.
inline double sidakAlpha(double familyAlpha, int tests) { return 1.0 - std::pow(1.0 - familyAlpha, 1.0 / tests); }

struct ChiSquareResult {
  double statistic = 0.0;
  int dof = 0;          ///< degrees of freedom: pooled cells − 1
  double pValue = 0.0;  ///< probability of a statistic at least this large if the null hypothesis holds
  int cells = 0;        ///< cells after pooling
};

/// Pearson's chi-square test of observed counts against expected counts (same total). Cells with
/// expected count below @p minExpected are pooled (in order of increasing expectation) until the
/// pool reaches it, as in Nori's warptest. Observations in a cell with expectation ~0 still count.
inline ChiSquareResult chiSquareTest(const std::vector<double>& observed, const std::vector<double>& expected,
                                     double minExpected = 5.0) {
  std::vector<size_t> order(expected.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return expected[i] < expected[j]; });
  // Pool cells in order of increasing expectation until each pooled cell reaches minExpected.
  std::vector<double> cellObs, cellExp;
  double poolObs = 0.0, poolExp = 0.0;
  for (size_t idx : order) {
    poolObs += observed[idx];
    poolExp += expected[idx];
    if (poolExp >= minExpected) {
      cellObs.push_back(poolObs);
      cellExp.push_back(poolExp);
      poolObs = poolExp = 0.0;
    }
  }
  if (poolObs > 0.0 || poolExp > 0.0) {
    if (cellExp.empty()) {
      cellObs.push_back(0.0);
      cellExp.push_back(0.0);
    }
    cellObs.back() += poolObs;  // a too-small remainder joins the last cell
    cellExp.back() += poolExp;
  }
  ChiSquareResult r;
  for (size_t i = 0; i < cellExp.size(); ++i) {
    const double e = std::max(cellExp[i], 1e-12);
    r.statistic += (cellObs[i] - e) * (cellObs[i] - e) / e;
  }
  r.cells = static_cast<int>(cellExp.size());
  r.dof = std::max(1, r.cells - 1);
  r.pValue = gammaQ(0.5 * r.dof, 0.5 * r.statistic);
  return r;
}

}  // namespace firstshot::test
