#pragma once
/// @file image_metrics.h
/// Error of a rendered image against a reference, as reported by firstshot-compare and plotted by
/// bench/firstshot_bench.py. Images are interleaved float RGB of the same size.
///
/// Definitions (x: test value, r: reference value, over every pixel and channel, N values):
///   ε          = epsilonFraction · mean(r)           (guards dark pixels; default fraction 0.01)
///   rel. RMSE  = sqrt( Σ ((x − r)/(r + ε))² / N )
///   MARE       = Σ |x − r|/(r + ε) / N               (mean absolute relative error)
///   NRMSE      = sqrt( Σ (x − r)² / N ) / mean(r)    (RMSE over the mean, for reference)
/// Values where x or r is not finite are counted in nonFinite and left out of every sum.
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

namespace firstshot::bench {

struct ImageErrors {
  double relRmse = 0;   ///< per-value relative RMSE (see the file comment)
  double mare = 0;      ///< mean absolute relative error
  double nrmse = 0;     ///< RMSE / mean(reference)
  double rmse = 0;      ///< plain RMSE
  double meanRef = 0;   ///< mean of the reference over the finite values
  double epsilon = 0;   ///< ε actually used
  size_t values = 0;    ///< finite values compared
  size_t nonFinite = 0; ///< values skipped because x or r is NaN or infinite
};

/// Errors of @p test against @p ref (same length). @throws std::invalid_argument on a size mismatch.
inline ImageErrors compareImages(std::span<const float> test, std::span<const float> ref, double epsilonFraction = 0.01) {
  if (test.size() != ref.size()) throw std::invalid_argument("images differ in size");
  ImageErrors e;
  double sumRef = 0;
  for (size_t k = 0; k < ref.size(); ++k) {
    if (!std::isfinite(test[k]) || !std::isfinite(ref[k])) {
      ++e.nonFinite;
      continue;
    }
    sumRef += ref[k];
    ++e.values;
  }
  if (e.values == 0) return e;
  e.meanRef = sumRef / double(e.values);
  e.epsilon = epsilonFraction * e.meanRef;
  double sq = 0, rel2 = 0, relAbs = 0;
  for (size_t k = 0; k < ref.size(); ++k) {
    if (!std::isfinite(test[k]) || !std::isfinite(ref[k])) continue;
    const double d = double(test[k]) - double(ref[k]);
    const double denom = std::abs(double(ref[k])) + e.epsilon;
    sq += d * d;
    const double rel = denom > 0 ? d / denom : 0.0;
    rel2 += rel * rel;
    relAbs += std::abs(rel);
  }
  const double n = double(e.values);
  e.rmse = std::sqrt(sq / n);
  e.nrmse = e.meanRef > 0 ? e.rmse / e.meanRef : 0.0;
  e.relRmse = std::sqrt(rel2 / n);
  e.mare = relAbs / n;
  return e;
}

/// Value-wise mean of two images of the same length. @throws std::invalid_argument on a size mismatch.
inline std::vector<float> meanImage(std::span<const float> a, std::span<const float> b) {
  if (a.size() != b.size()) throw std::invalid_argument("images differ in size");
  std::vector<float> m(a.size());
  for (size_t k = 0; k < a.size(); ++k) m[k] = 0.5f * (a[k] + b[k]);
  return m;
}

}  // namespace firstshot::bench
