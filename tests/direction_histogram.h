#pragma once
/// @file direction_histogram.h
/// Equal-area histogram of unit directions for chi-square tests of sampling routines. Cells are
/// uniform in z' ∈ [zMin, 1] and φ' ∈ [0, 2π) (dω = dz' dφ'), measured in a chosen frame (so a
/// narrow lobe can be resolved by putting the frame's z on its axis and raising zMin); directions
/// with z' < zMin share one extra cell.
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/util/math.h"

namespace firstshot::test {

class SphereHistogram {
 public:
  SphereHistogram(int zBins, int phiBins, const Frame& frame = Frame(), double zMin = -1.0)
      : zBins_(zBins), phiBins_(phiBins), frame_(frame), zMin_(zMin),
        counts_(static_cast<size_t>(zBins * phiBins) + (zMin > -1.0 ? 1 : 0), 0.0) {}

  /// Cell of a unit direction (given in world coordinates).
  int cell(const Vec3& world) const {
    const Vec3 w = frame_.toLocal(world);
    const double z = std::clamp(static_cast<double>(w.z), -1.0, 1.0);
    if (z < zMin_) return zBins_ * phiBins_;
    double phi = std::atan2(static_cast<double>(w.y), static_cast<double>(w.x));
    if (phi < 0.0) phi += 2.0 * kPi;
    const int iz = std::min(zBins_ - 1, static_cast<int>((z - zMin_) / (1.0 - zMin_) * zBins_));
    const int ip = std::min(phiBins_ - 1, static_cast<int>(phi / (2.0 * kPi) * phiBins_));
    return iz * phiBins_ + ip;
  }
  void add(const Vec3& w) {
    counts_[static_cast<size_t>(cell(w))] += 1.0;
    ++total_;
  }
  const std::vector<double>& counts() const { return counts_; }
  /// Number of directions added.
  double total() const { return total_; }

  /// Expected counts of total() directions drawn with solid-angle density @p pdf (a callable taking a
  /// world direction), conditioned on the sample being a direction: cell masses are integrated by
  /// the midpoint rule with k×k points per cell and divided by their sum, so a small global error of
  /// the quadrature does not bias the test. Sets @p integral to ∫pdf dω over the whole sphere (the
  /// probability that a sample succeeds, for a separate check).
  template <typename Pdf>
  std::vector<double> expected(const Pdf& pdf, int k, double* integral = nullptr) const {
    std::vector<double> mass(counts_.size(), 0.0);
    integrate(pdf, zMin_, 1.0, zBins_, k, mass.data());
    if (zMin_ > -1.0) {
      const int belowBins = std::max(64, zBins_);
      std::vector<double> below(static_cast<size_t>(belowBins * phiBins_), 0.0);
      integrate(pdf, -1.0, zMin_, belowBins, k, below.data());
      for (double m : below) mass.back() += m;
    }
    double sum = 0.0;
    for (double m : mass) sum += m;
    if (integral) *integral = sum;
    for (double& m : mass) m = sum > 0.0 ? m / sum * total_ : 0.0;
    return mass;
  }

 private:
  template <typename Pdf>
  void integrate(const Pdf& pdf, double z0, double z1, int zBins, int k, double* out) const {
    const double dz = (z1 - z0) / zBins, dphi = 2.0 * kPi / phiBins_;
    for (int iz = 0; iz < zBins; ++iz)
      for (int ip = 0; ip < phiBins_; ++ip) {
        double sum = 0.0;
        for (int a = 0; a < k; ++a)
          for (int b = 0; b < k; ++b) {
            const double z = z0 + dz * (iz + (a + 0.5) / k);
            const double phi = dphi * (ip + (b + 0.5) / k);
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const Vec3 local(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                             static_cast<float>(z));
            sum += pdf(frame_.toWorld(local));
          }
        out[iz * phiBins_ + ip] = sum * dz * dphi / (k * k);
      }
  }

  int zBins_, phiBins_;
  Frame frame_;
  double zMin_;
  std::vector<double> counts_;
  double total_ = 0.0;
};

}  // namespace firstshot::test
