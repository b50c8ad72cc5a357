#pragma once
/// @file distribution_1d.h
/// A piecewise-constant distribution tabulated from n non-negative cell values: the one inversion of a tabulated CDF
/// (pbrt's Distribution1D idea, written here from the definition). One table, two views:
/// - continuous, a density over [0, 1) with n equal cells: sample() and pdf() (f(cell) / ∫f), the rows and marginal
///   of Distribution2D (common/sampling/distribution_2d.h, the environment map);
/// - discrete, an index chosen by weight: sampleDiscrete() (the cell and the rest of u inside it, for the next choice),
///   probability() (the width of the cell's CDF interval, exactly what sampleDiscrete draws with): lights by power,
///   an emitter's triangles by area, an IES table's cells.
/// The CDF is summed in double in cell order, each partial sum stored in Real and divided by the total (the last
/// entry set to 1), so a float table costs half the memory and rounds as a float CDF summed in double does. The
/// inversion finds u's cell by a guide table (the cells around u's bucket of n equal buckets: O(1) expected), which
/// gives the answer of a binary search over the whole CDF.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace firstshot {

/// @tparam Real the stored CDF's type (float or double); sums are always double.
template <typename Real>
class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  /// @param values the n cell values (negative and NaN ones count as 0). All zero: uniform, so sampling never fails.
  explicit PiecewiseConstant1D(const std::vector<double>& values);

  size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  /// Σ of the cell values (0 when all are zero), the discrete view's normalisation.
  double total() const { return total_; }
  /// ∫ f over [0, 1): the mean of the cell values.
  double integral() const { return integral_; }
  /// The value of cell @p i (as counted: at least 0).
  Real value(size_t i) const { return values_[i]; }

  /// Sample x ∈ [0, 1) from u ∈ [0, 1): returns x and sets @p cell and @p pdf (density in x, f(cell)/∫f).
  /// @pre !empty()
  double sample(double u, size_t& cell, double& pdf) const;
  /// Density at @p x ∈ [0, 1).
  double pdf(double x) const;

  /// The cell whose CDF interval [cdf_i, cdf_i+1) holds @p u ∈ [0, 1) (a cell of zero width is never chosen) and, in
  /// @p remainder when given, u's position inside that interval, in [0, 1) (½ in a cell of zero width, which only
  /// u outside [0, 1) reaches). @pre !empty()
  size_t sampleDiscrete(Real u, Real* remainder = nullptr) const;
  /// The probability that sampleDiscrete returns cell @p i: the width of its CDF interval.
  Real probability(size_t i) const { return cdf_[i + 1] - cdf_[i]; }

 private:
  /// The first cell whose CDF end exceeds @p u, at most n − 1.
  size_t find(double u) const;

  std::vector<Real> values_;  ///< clamped at 0
  std::vector<Real> cdf_;     ///< size() + 1 entries, cdf_[0] = 0, cdf_.back() = 1
  /// guide_[b] = the first cell whose CDF end exceeds b/n, b = 0 … n.
  std::vector<uint32_t> guide_;
  double total_ = 0, integral_ = 0;
};

/// The double-precision table (environment maps, IES cells, emitters by power, luminaire particles).
using Distribution1D = PiecewiseConstant1D<double>;
/// The single-precision table, for per-light tables sampled with float numbers (triangles by area).
using Distribution1Df = PiecewiseConstant1D<float>;

extern template class PiecewiseConstant1D<float>;
extern template class PiecewiseConstant1D<double>;

}  // namespace firstshot
