#pragma once
/// @file coverage.h
/// The remedy for item-buffer aliasing (../shared/REFERENCE.md, "Aliasing"): the item buffer only
/// estimates WHICH PART of a patch is visible; how much light the whole patch would receive comes
/// from closed-form integrals. For a patch j seen from a light sample,
///   r_ij = U_j · V_j,   V_j = Σ_{pixels showing j} w_p / Σ_{pixel centres inside j's projection} w_p,
/// where U_j is the unoccluded integral of the window weight over the patch (solid angle, cosine-
/// weighted solid angle or projected area) and the denominator rasterises the patch alone in
/// software at the same pixel centres. An unoccluded patch gets V_j = 1 and so its exact value.
#include <vector>

#include "common/math.h"
#include "preprocess/view.h"

namespace fs {

/// Σ of @p weights over the pixel centres of @p view that fall inside the convex planar polygon
/// @p poly (3 or 4 vertices), ignoring occlusion; the polygon is clipped to depth ≥ @p near first.
/// Also returns the number of such pixels in @p pixels.
double coveredWeight(const View& view, const std::vector<double>& weights, const Vec3d* poly, int count, double near,
                     size_t& pixels);

/// ∫ dω over the polygon seen from @p eye (its solid angle).
double unoccludedSolidAngle(const Vec3d& eye, const Vec3d* poly, int count);

/// ∫ cosθ dω over the part of the polygon above the plane through @p eye with normal @p n
/// (the hemicube's weight integrated: π × the point-to-polygon form factor).
double unoccludedCosineSolidAngle(const Vec3d& eye, const Vec3d& n, const Vec3d* poly, int count);

/// Projected area of the polygon perpendicular to @p direction, m².
double unoccludedProjectedArea(const Vec3d& direction, const Vec3d* poly, int count);

}  // namespace fs
