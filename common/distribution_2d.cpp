#include "common/distribution_2d.h"

#include <algorithm>

namespace fs {

Distribution1D::Distribution1D(std::vector<double> values) : values_(std::move(values)) {
  const size_t n = values_.size();
  cdf_.assign(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + std::max(values_[i], 0.0) / static_cast<double>(n);
  integral_ = cdf_[n];
  if (!(integral_ > 0.0)) {  // all zero: uniform
    for (size_t i = 0; i <= n; ++i) cdf_[i] = static_cast<double>(i) / static_cast<double>(n);
    return;
  }
  for (size_t i = 1; i <= n; ++i) cdf_[i] /= integral_;
  cdf_[n] = 1.0;
}

double Distribution1D::sample(double u, size_t& cell, double& pdf) const {
  const size_t n = values_.size();
  // The last cell whose CDF start is ≤ u (cells of zero width are never chosen: upper_bound skips them).
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  cell = std::min<size_t>(static_cast<size_t>(std::max<std::ptrdiff_t>(it - cdf_.begin() - 1, 0)), n - 1);
  const double width = cdf_[cell + 1] - cdf_[cell];
  const double t = width > 0 ? (u - cdf_[cell]) / width : 0.5;
  pdf = integral_ > 0 ? std::max(values_[cell], 0.0) / integral_ : 1.0;
  return std::min((static_cast<double>(cell) + std::clamp(t, 0.0, 1.0)) / static_cast<double>(n),
                  std::nextafter(1.0, 0.0));
}

double Distribution1D::pdf(double x) const {
  const size_t n = values_.size();
  const size_t cell = std::min(static_cast<size_t>(std::max(x, 0.0) * static_cast<double>(n)), n - 1);
  return integral_ > 0 ? std::max(values_[cell], 0.0) / integral_ : 1.0;
}

Distribution2D::Distribution2D(const std::vector<double>& values, size_t nu, size_t nv) {
  rows_.reserve(nv);
  std::vector<double> rowIntegrals(nv);
  for (size_t v = 0; v < nv; ++v) {
    rows_.emplace_back(std::vector<double>(values.begin() + v * nu, values.begin() + (v + 1) * nu));
    rowIntegrals[v] = rows_.back().integral();
  }
  marginal_ = Distribution1D(std::move(rowIntegrals));
}

Vec2d Distribution2D::sample(const Vec2d& xi, double& pdf) const {
  size_t row = 0, cell = 0;
  double pv = 0, pu = 0;
  const double v = marginal_.sample(xi.y, row, pv);
  const double u = rows_[row].sample(xi.x, cell, pu);
  pdf = pv * pu;
  return {u, v};
}

double Distribution2D::pdf(const Vec2d& uv) const {
  const size_t nv = rows_.size();
  const size_t row = std::min(static_cast<size_t>(std::max(uv.y, 0.0) * static_cast<double>(nv)), nv - 1);
  return marginal_.pdf(uv.y) * rows_[row].pdf(uv.x);
}

}  // namespace fs
