#pragma once
/// @file reflected.h
/// The reflected first-shot radiance of one patch, Σ_i e_i · w_i · f_r(ω'_i, x, ω) over the
/// patch's factors: the one loop behind both of the renderer's evaluations of it, per hit point
/// (FirstShotLighting::eval: w_i the visible fraction times the exact kernel at x, or r_ij) and per
/// patch at its centroid (the bundle transfer: w_i = r_ij, the patch average).
#include <cstdint>

#include "common/materials/bsdf.h"
#include "common/table/firstshot.h"
#include "common/util/math.h"
#include "render/scene/table_rows.h"

namespace firstshot {

/// ω'_i of the first-shot term: the unit direction from @p x towards light sample @p s (against the
/// travel direction for a directional light).
inline Vec3 firstShotDirection(const LightSample& s, const Vec3& x) {
  return s.kind == LightSampleKind::Directional ? -s.normal : glm::normalize(s.position - x);
}

/// How a term e_i · w_i · f_r is multiplied out. Floating-point products are not associative:
/// each evaluation keeps the order it always had, so that its images stay the same bit for bit.
enum class FirstShotProduct : uint8_t {
  EmissionLast,   ///< e_i · (w_i · f_r)   (FirstShotLighting::eval)
  EmissionFirst,  ///< (e_i · w_i) · f_r   (the bundle transfer)
};

/// Adds Σ_i e_i · w_i · f_r(ω'_i, x, ω) over the factors of @p row, in the row's order, to @p sum
/// and returns it: e_i the emission of @p samples[i], ω'_i towards sample i from @p x (unless
/// @p weight changes it), ω = @p woLocal (in @p frame), w_i = r_ij unless @p weight changes it.
/// @p weight(const TableFactor&, const LightSample&, Vec3& wi, float& w) -> bool may replace w_i
/// and ω'_i; false leaves the factor out.
template <class Weight>
Color sumReflectedFirstShot(const std::vector<LightSample>& samples, TableRow row, const Vec3& x, const Frame& frame,
                            const Vec3& woLocal, const BSDF& bsdf, FirstShotProduct product, Color sum,
                            Weight&& weight) {
  for (const TableFactor factor : row) {
    const LightSample& s = samples[factor.sample];
    Vec3 wi = firstShotDirection(s, x);
    float w = factor.r;
    if (!weight(factor, s, wi, w)) continue;
    const Color f = bsdf.eval(BSDFQuery(frame.toLocal(wi), woLocal));
    if (product == FirstShotProduct::EmissionLast)
      sum += s.emission * (w * f);
    else
      sum += s.emission * w * f;
  }
  return sum;
}

}  // namespace firstshot
