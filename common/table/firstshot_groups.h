#pragma once
/// @file firstshot_groups.h
/// Grouped factors: the compact on-disk form of a first-shot table's CSR (docs/firstshot-format.md,
/// section CSRR, version 3).
///
/// The analytic estimator writes, for a point light or an area-light vertex i and a patch j,
///   r_ij = float(scale_i · (V_ij · U_ij) / A_j)
/// with U_ij a closed form (analyticIntegral below), scale_i = 1/(4π) or S_i/3, and V_ij ∈ (0, 1] the
/// visible fraction. Where every vertex of one area light sees patch j with the same fraction V (the
/// common case: V = 1, the patch fully visible), the row stores ONE group (light, V) and the reader
/// recomputes the factors with the same closed forms in the same double arithmetic: the expansion is
/// bit-identical to the factors the preprocessor wrote, and the writer checks that it is before it
/// groups (a row whose factors would not come back exactly keeps them as single entries).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/table/firstshot.h"

namespace firstshot {

/// The eye of an analytic window placed at sample @p s: the sample's position, moved @p eyeOffset
/// metres along its normal for an area vertex (preprocess/window.h, areaLightEyeOffset).
Vec3d analyticEye(const LightSample& s, double eyeOffset);

/// scale_i: 1/(4π) for a point light, S_i/3 (LightSample::weight, m²) for an area vertex; 0 otherwise.
double analyticScale(const LightSample& s);

/// U_ij, the unoccluded closed-form integral of sample @p s's window weight over patch @p p, its eye
/// @p eyeOffset off the sample (analyticEye): the solid angle (sr) for a point light, the cosine-
/// weighted solid angle about the sample's normal, clipped to its hemisphere (sr), for an area
/// vertex; 0 for spots and directional lights (not handled here).
double analyticIntegral(const LightSample& s, double eyeOffset, const Patch& p);

/// r_ij from its parts, in the one arithmetic order the preprocessor and the reader share:
/// float(scale · (fraction · U) / area) (1/m² for points, sr for area vertices).
inline float analyticFactor(double scale, double fraction, double U, double area) {
  return static_cast<float>(scale * (fraction * U) / area);
}

/// V_ij recovered from a factor of a point light or an area vertex: r·A/(scale·U) (1 for a patch the
/// analytic estimator found fully visible, up to the float rounding of r), or −1 where scale·U ≤ 0.
inline float recoveredVisible(float r, double scale, double U, double area) {
  const double scaledU = scale * U;
  return scaledU > 0 ? static_cast<float>(double(r) * area / scaledU) : -1.0f;
}

/// recoveredVisible for factor @p r of sample @p s on patch @p p (−1 for spots and directional lights).
float recoveredVisible(float r, const LightSample& s, double eyeOffset, const Patch& p);

/// The CSRR section's contents (version 3): per patch row, single factors (sample, r_ij) and groups
/// (area light, V), each a CSR over the patches by its per-row counts.
struct GroupedFactors {
  std::vector<uint32_t> rowCount;     ///< expanded factors per row (the in-memory row length)
  std::vector<uint32_t> singleCount;  ///< single entries per row
  std::vector<uint32_t> groupCount;   ///< groups per row
  std::vector<uint32_t> singleSample; ///< light sample of each single entry, ascending within a row
  std::vector<float> singleFactor;    ///< its r_ij
  std::vector<uint32_t> groupLight;   ///< SceneDesc light index of each group, ascending within a row
  std::vector<float> groupVisible;    ///< its common visible fraction V ∈ (0, 1]
};

/// Splits the table's factors into singles and groups. Groups are made only for analytic-estimator
/// tables, for the area-vertex samples of one light that all see the patch (U > 0), with at least two
/// factors, and only when the expansion reproduces every one of them bit for bit.
GroupedFactors groupFactors(const FirstShotTable& t);

/// Rebuilds rowStart, sampleIndex, factor and visible of @p t (mesh, samples, settings and areaEyeOffset set)
/// from @p g, whose rows must hold @p nonZeros factors in all. Every inconsistency (counts that do not
/// add up, a light without area vertices, V outside (0, 1], a sample out of range or listed twice, a
/// row whose expansion does not have its stored length, an invalid factor) is reported by @p fail
/// with a message; fail must not return. Rows are expanded in parallel.
void expandFactors(const GroupedFactors& g, uint64_t nonZeros, FirstShotTable& t,
                   const std::function<void(const std::string&)>& fail);

}  // namespace firstshot
