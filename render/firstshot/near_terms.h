#pragma once
/// @file near_terms.h
/// The first-shot samples that a patch evaluates at every point (FirstShotLighting's near point
/// lights and area-light vertices), stored per patch in blocks of kLanes structure-of-arrays lanes
/// so that their sum at a point runs four terms at a time (SSE2 where the target has it).
#include <cstdint>
#include <vector>

#include "common/util/math.h"

namespace firstshot {

class NearTerms {
 public:
  static constexpr uint32_t kLanes = 4;

  /// Empties the set, ready for patch 0's terms.
  void clear();
  /// A point light at @p position: coefficient · cosθ_x/d² (the 1/4π folded into @p coefficient).
  void addPoint(const Vec3& position, const Color& coefficient);
  /// An area-light vertex at @p position with the light's unit @p normal:
  /// coefficient · cosθ_x·cosθ_L/d².
  void addArea(const Vec3& position, const Vec3& normal, const Color& coefficient);
  /// Closes the current patch's terms (padding its last block with zero terms); the next ones
  /// belong to the next patch. Call once per patch, in patch order.
  void endPatch();

  /// Σ over patch @p patch's terms at point @p x on the side of unit normal @p n (W/m² when the
  /// coefficients are emission × V_ij × the kernel's constant). Terms behind x's plane, or with x
  /// behind an area vertex's light, give 0.
  Color sum(uint32_t patch, const Vec3& x, const Vec3& n) const;
  /// sum() without SSE, the same arithmetic lane by lane: bit for bit the same result (what sum()
  /// runs on targets without SSE2; tests compare the two).
  Color sumPortable(uint32_t patch, const Vec3& x, const Vec3& n) const;

 private:
  void add(const Vec3& position, const Vec3& normal, float point, const Color& coefficient);
  std::vector<uint32_t> blockStart_{0};  ///< per patch: its first block; blockStart_[j + 1] ends it
  /// Per lane: position, light normal (0 for points), 1 for a point light (cosθ_L·d = d), coefficient.
  std::vector<float> px_, py_, pz_, nx_, ny_, nz_, point_, cr_, cg_, cb_;
};

}  // namespace firstshot
