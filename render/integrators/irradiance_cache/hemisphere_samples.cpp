// Irradiance, harmonic mean distance and gradients from stratified hemisphere samples.
#include "render/integrators/irradiance_cache/hemisphere_samples.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace firstshot {

void HemisphereSamples::estimate(const Frame& frame, bool gradients, IrradianceRecord& rec) const {
  const int M = M_, N = N_;
  const double cells = double(M) * double(N);
  Vec3d sum(0.0);
  double invDist = 0;
  for (size_t i = 0; i < L_.size(); ++i) {
    sum += Vec3d(L_[i]);
    if (std::isfinite(r_[i]) && r_[i] > 0.0f) invDist += 1.0 / r_[i];
  }
  rec.E = Color(sum * (kPi / cells));
  rec.R = invDist > 0 ? float(cells / invDist) : std::numeric_limits<float>::infinity();
  for (int c = 0; c < 3; ++c) rec.gradR[c] = rec.gradT[c] = Vec3(0.0f);
  if (!gradients) return;

  Vec3d gr[3] = {Vec3d(0.0), Vec3d(0.0), Vec3d(0.0)}, gt[3] = {Vec3d(0.0), Vec3d(0.0), Vec3d(0.0)};
  for (int j = 0; j < M; ++j) {
    const double sin2Minus = double(j) / M;
    const double sinMinus = std::sqrt(sin2Minus), sinPlus = std::sqrt(double(j + 1) / M);
    // Mean of tanθ over the cell (uniform in u = sin²θ): ∫ √(u/(1−u)) du = asin √u − √(u(1−u)).
    auto F = [](double u) { return std::asin(std::sqrt(u)) - std::sqrt(u * (1.0 - u)); };
    const double tanMean = M * (F(double(j + 1) / M) - F(sin2Minus));
    for (int k = 0; k < N; ++k) {
      const double phiCentre = 2.0 * kPi * (k + 0.5) / N, phiMinus = 2.0 * kPi * k / N, phiPlus = 2.0 * kPi * (k + 1) / N;
      const Vec3d L(Lc(j, k));
      // Rotation: the cell's mean of tanθ (−sin φ, cos φ, 0) (finite, unlike tanθ at the horizon).
      const Vec3d v = tanMean * N / (2.0 * kPi) *
                      Vec3d(std::cos(phiPlus) - std::cos(phiMinus), std::sin(phiPlus) - std::sin(phiMinus), 0.0);
      for (int c = 0; c < 3; ++c) gr[c] += v * L[c];
      // Translation across the polar boundary with cell (j−1, k).
      if (j > 0) {
        const double rmin = std::min(rc(j, k), rc(j - 1, k));
        if (std::isfinite(rmin) && rmin > 0) {
          const Vec3d u(std::cos(phiCentre), std::sin(phiCentre), 0.0);
          const Vec3d dL = L - Vec3d(Lc(j - 1, k));
          const double coef = 2.0 * kPi / N * sinMinus * (1.0 - sin2Minus) / rmin;
          for (int c = 0; c < 3; ++c) gt[c] += u * (coef * dL[c]);
        }
      }
      // Translation across the azimuthal boundary with cell (j, k−1).
      const int km = (k + N - 1) % N;
      const double rmin = std::min(rc(j, k), rc(j, km));
      if (std::isfinite(rmin) && rmin > 0) {
        const Vec3d vm(-std::sin(phiMinus), std::cos(phiMinus), 0.0);
        const Vec3d dL = L - Vec3d(Lc(j, km));
        const double coef = (sinPlus - sinMinus) / rmin;
        for (int c = 0; c < 3; ++c) gt[c] += vm * (coef * dL[c]);
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    rec.gradR[c] = frame.toWorld(Vec3(gr[c] * (kPi / cells)));
    rec.gradT[c] = frame.toWorld(Vec3(gt[c]));
  }
}

}  // namespace firstshot
