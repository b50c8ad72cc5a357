#pragma once
/// @file distribution_2d.h
/// Piecewise-constant densities for importance sampling a tabulated function (pbrt's Distribution1D/2D idea, written
/// here from the definition): 1D over [0, 1) with n equal cells, 2D over [0, 1)² with nu × nv cells as a marginal over
/// rows and a conditional within each row. Sampling inverts the CDF exactly (continuous within a cell), so the
/// density of a sample is f(cell) / ∫f, the same value pdf() returns. Used by the environment map (render/lights/environment_map.h).
#include <cstdint>
#include <vector>

#include "common/math.h"

namespace fs {

/// A density over [0, 1) proportional to n non-negative cell values. All zero: uniform (so sampling never fails).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<double> values);

  size_t size() const { return values_.size(); }
  /// ∫ f over [0, 1): the mean of the cell values.
  double integral() const { return integral_; }
  /// Sample x ∈ [0, 1) from u ∈ [0, 1): returns x and sets @p cell and @p pdf (density in x, f(cell)/∫f).
  double sample(double u, size_t& cell, double& pdf) const;
  /// Density at @p x ∈ [0, 1).
  double pdf(double x) const;

 private:
  std::vector<double> values_, cdf_;  ///< cdf_ has size() + 1 entries, cdf_[0] = 0, cdf_.back() = 1
  double integral_ = 0;
};

/// A density over [0, 1)² proportional to a row-major nu × nv grid of non-negative values (u along a row).
class Distribution2D {
 public:
  Distribution2D() = default;
  /// @param values nu × nv values, row v at values[v * nu .. v * nu + nu)
  Distribution2D(const std::vector<double>& values, size_t nu, size_t nv);

  /// Sample (u, v) ∈ [0, 1)² from @p xi; sets @p pdf to the density in (u, v).
  Vec2d sample(const Vec2d& xi, double& pdf) const;
  /// Density at (u, v) ∈ [0, 1)².
  double pdf(const Vec2d& uv) const;
  double integral() const { return marginal_.integral(); }

 private:
  std::vector<Distribution1D> rows_;
  Distribution1D marginal_;
};

}  // namespace fs
