#pragma once
/// @file distribution_2d.h
/// A piecewise-constant density over [0, 1)² with nu × nv cells, as a marginal over rows and a conditional within
/// each row (pbrt's Distribution2D idea, written here from the definition; the 1D tables are common/sampling/distribution_1d.h).
/// Sampling inverts the CDFs exactly (continuous within a cell), so the density of a sample is f(cell) / ∫f, the same
/// value pdf() returns. Used by the environment map.
#include <cstddef>
#include <vector>

#include "common/sampling/distribution_1d.h"
#include "common/util/math.h"

namespace firstshot {

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

}  // namespace firstshot
