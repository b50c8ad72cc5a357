#include "common/sampling/distribution_2d.h"

#include <algorithm>

namespace firstshot {

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

}  // namespace firstshot
