#pragma once
/// @file hemisphere_samples.h
/// The primary method's samples of one irradiance record: M × N cells of equal projected solid
/// angle (cell (j, k) spans sin²θ ∈ [j/M, (j+1)/M), φ ∈ [2πk/N, 2π(k+1)/N); see
/// squareToCosineHemisphereStratum), one ray per cell, and the estimates made from them:
/// - E = π/(MN) Σ L_jk (Ward et al. 1988, eq. 2 in cosine-weighted form);
/// - R = MN / Σ 1/r_jk, the harmonic mean of the hit distances (rays that escape add 0);
/// - Ward & Heckbert (1992) gradients, in the record's frame (z = normal):
///   rotational  ∇r E = π/(MN) Σ_jk L_jk ⟨tanθ (−sin φ, cos φ, 0)⟩_jk, the bracket the mean over
///               cell (j, k) (exact for L constant in each cell, and finite at the horizon where
///               tanθ is not), so that E(N') ≈ E + ∇r E·(N × N');
///   translational ∇t E = Σ_k [ u_k (2π/N) Σ_{j≥1} sinθ_j− cos²θ_j− / min(r_jk, r_j−1,k) (L_jk − L_j−1,k)
///                             + v_k− Σ_j (sinθ_j+ − sinθ_j−) / min(r_jk, r_j,k−1) (L_jk − L_j,k−1) ],
///               with sin²θ_j− = j/M, sin²θ_j+ = (j+1)/M, u_k the horizontal direction of the cell
///               centre's azimuth, v_k− the horizontal direction perpendicular to the cell's
///               boundary φ = 2πk/N (towards larger φ), and k−1 taken cyclically. Each term is the
///               change of the projected solid angle of a cell boundary as the point moves, with
///               the boundary held by the nearer of the two surfaces seen.
#include <vector>

#include "common/util/math.h"
#include "render/integrators/irradiance_cache/cache.h"

namespace firstshot {

class HemisphereSamples {
 public:
  /// @param M polar strata, @param N azimuthal strata (Ward: N = 2M)
  HemisphereSamples(int M, int N) : M_(M), N_(N), L_(size_t(M) * size_t(N), Color(0.0f)), r_(size_t(M) * size_t(N), 0.0f) {}
  int M() const { return M_; }
  int N() const { return N_; }
  /// Radiance arriving through cell (j, k).
  Color& L(int j, int k) { return L_[size_t(j) * size_t(N_) + size_t(k)]; }
  /// Distance to the surface the ray of cell (j, k) hit; infinity if it escaped.
  float& r(int j, int k) { return r_[size_t(j) * size_t(N_) + size_t(k)]; }

  /// Sets rec.E and rec.R, and with @p gradients rec.gradR and rec.gradT (world space through
  /// @p frame, whose z axis is the record's normal); without, the gradients are zero.
  void estimate(const Frame& frame, bool gradients, IrradianceRecord& rec) const;

 private:
  Color Lc(int j, int k) const { return L_[size_t(j) * size_t(N_) + size_t(k)]; }
  float rc(int j, int k) const { return r_[size_t(j) * size_t(N_) + size_t(k)]; }
  int M_, N_;
  std::vector<Color> L_;
  std::vector<float> r_;
};

}  // namespace firstshot
