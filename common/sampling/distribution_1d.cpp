#include "common/sampling/distribution_1d.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace firstshot {

template <typename Real>
PiecewiseConstant1D<Real>::PiecewiseConstant1D(const std::vector<double>& values) {
  const size_t n = values.size();
  values_.resize(n);
  cdf_.assign(n + 1, Real(0));
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double v = values[i] > 0 ? values[i] : 0.0;  // negative and NaN values count as 0
    values_[i] = Real(v);
    sum += v;
    cdf_[i + 1] = Real(sum);
  }
  total_ = sum > 0 ? sum : 0.0;
  integral_ = n > 0 ? total_ / static_cast<double>(n) : 0.0;
  if (n == 0) return;
  if (!(sum > 0)) {  // all zero: uniform
    for (size_t i = 0; i <= n; ++i) cdf_[i] = Real(static_cast<double>(i) / static_cast<double>(n));
  } else {
    for (size_t i = 1; i <= n; ++i) cdf_[i] = Real(double(cdf_[i]) / sum);
    cdf_[n] = Real(1);
  }
  guide_.resize(n + 1);
  for (size_t b = 0; b <= n; ++b)
    guide_[b] = uint32_t(std::upper_bound(cdf_.begin() + 1, cdf_.end(), static_cast<double>(b) / static_cast<double>(n),
                                          [](double x, Real c) { return x < double(c); }) -
                         (cdf_.begin() + 1));
}

template <typename Real>
size_t PiecewiseConstant1D<Real>::find(double u) const {
  // A bucket's cells lie between the guides of its neighbours (u·n may round across a bucket's edge); the binary
  // search over that range gives the answer of one over the whole CDF.
  const size_t n = values_.size(), b = std::min(size_t(std::max(u, 0.0) * static_cast<double>(n)), n - 1);
  const Real* ends = cdf_.data() + 1;  // cell i's CDF interval ends at ends[i]
  const Real* lo = ends + guide_[b > 0 ? b - 1 : 0];
  const Real* hi = ends + std::min<size_t>(n, size_t(guide_[std::min(b + 2, n)]) + 1);
  const Real* it = std::upper_bound(lo, hi, u, [](double x, Real c) { return x < double(c); });
  return std::min(size_t(it - ends), n - 1);
}

template <typename Real>
double PiecewiseConstant1D<Real>::sample(double u, size_t& cell, double& pdf) const {
  const size_t n = values_.size();
  cell = find(u);
  const double lo = double(cdf_[cell]), width = double(cdf_[cell + 1]) - lo;
  const double t = width > 0 ? (u - lo) / width : 0.5;
  pdf = integral_ > 0 ? double(values_[cell]) / integral_ : 1.0;
  return std::min((static_cast<double>(cell) + std::clamp(t, 0.0, 1.0)) / static_cast<double>(n),
                  std::nextafter(1.0, 0.0));
}

template <typename Real>
double PiecewiseConstant1D<Real>::pdf(double x) const {
  const size_t n = values_.size();
  const size_t cell = std::min(static_cast<size_t>(std::max(x, 0.0) * static_cast<double>(n)), n - 1);
  return integral_ > 0 ? double(values_[cell]) / integral_ : 1.0;
}

template <typename Real>
size_t PiecewiseConstant1D<Real>::sampleDiscrete(Real u, Real* remainder) const {
  const size_t i = find(double(u));
  if (remainder) {
    const Real lo = cdf_[i], width = cdf_[i + 1] - lo;
    constexpr Real kBelowOne = Real(1) - std::numeric_limits<Real>::epsilon() / Real(2);  // the largest Real < 1
    *remainder = width > 0 ? std::clamp((u - lo) / width, Real(0), kBelowOne) : Real(0.5);
  }
  return i;
}

template class PiecewiseConstant1D<float>;
template class PiecewiseConstant1D<double>;

}  // namespace firstshot
