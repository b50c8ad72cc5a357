#pragma once
/// @file coverage.h
/// The remedy for item-buffer aliasing (docs/firstshot-format.md, "Estimators"): the item buffer only
/// estimates WHICH PART of a patch is visible; how much light the whole patch would receive comes
/// from closed-form integrals. For a patch j seen from a light sample,
///   r_ij = U_j · V_j,   V_j = Σ_{pixels showing j} w_p / Σ_{pixel centres inside j's projection} w_p,
/// where U_j is the unoccluded integral of the window weight over the patch (solid angle, cosine-
/// weighted solid angle or projected area) and the denominator rasterises the patch alone in
/// software at the same pixel centres. An unoccluded patch gets V_j = 1 and so its exact value.
#include <cstdint>
#include <vector>

#include "common/patches/patches.h"
#include "common/util/math.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/exposure.h"
#include "preprocess/view.h"

namespace firstshot {

/// Σ of @p weights over the pixel centres of @p view that fall inside the convex planar polygon
/// @p poly (3 or 4 vertices), ignoring occlusion; the polygon is clipped to depth ≥ @p near first.
/// Also returns the number of such pixels in @p pixels.
double coveredWeight(const View& view, const std::vector<double>& weights, const Vec3d* poly, int count, double near,
                     size_t& pixels);

/// One patch's pixel centres in one view: the weight of all of them (occlusion ignored) and of those
/// from which the patch is the nearest surface.
struct PatchCoverage {
  double expected = 0;  ///< Σ w over the pixel centres inside the patch's projection
  double visible = 0;   ///< Σ w over those of them where the patch is visible
  size_t pixels = 0;    ///< number of pixel centres inside the projection (w > 0)
};

/// The visible fraction's two sums for patch @p patch of @p mesh in @p view, whose item buffer is
/// @p ids. The item buffer only proposes occluders: at a centre inside the patch's projection, the
/// patch counts as visible unless a patch seen at that pixel or one of its 8 neighbours is hit by
/// the centre's ray, in double precision, strictly nearer (depth ≥ @p near) than the patch itself.
/// Numerator and denominator so use the same pixel centres and the same exact geometry: where
/// patches meet (shared edges, corners, contact lines) the rasteriser's rules, subpixel snapping and
/// depth precision no longer move weight from a patch to its neighbour (a loss, since a fraction is
/// clamped at 1), and an unoccluded patch gets exactly 1.
/// With @p exposure, centres whose point on the patch is buried (preprocess/exposure.h) count in
/// neither sum.
/// With @p cutouts, an occluder proposed on a cut-out patch occludes only where its surface exists, and
/// on a mask cut-out patch itself the centres over its holes count in neither sum, as buried ones: the fraction is
/// that of its existing part (the receiving factor is the irradiance at its solid points; a blend patch's points all
/// count).
PatchCoverage patchCoverage(const View& view, const std::vector<double>& weights, const std::vector<uint32_t>& ids,
                            const PatchMesh& mesh, uint32_t patch, double near, const ExposureQuery* exposure = nullptr,
                            const PatchCutouts* cutouts = nullptr);

/// The ray that decides the visibility of the point @p x from the common eye of @p views (a window placed at one
/// light sample, with its weights): the first view whose pixel under x has a non-zero weight decides, by a ray from
/// the eye (orthographic views: from the image plane) to x: x is visible unless the ray origin + t·(x − origin) meets
/// a patch for t in [0, kPointRayEnd] (EmbreeItemBuffer::occluded, several points' rays at once). For patches too
/// small to hold enough pixel centres, whose occluders may be made of patches smaller than a pixel too (so that the
/// item buffer cannot propose them). @return false if x is in no view (behind a hemicube's base, outside the window),
/// else true with the ray's origin in @p origin.
bool pointVisibilityRay(const std::vector<View>& views, const std::vector<std::vector<double>>& weights, const Vec3d& x,
                        double near, Vec3d& origin);
/// How far along pointVisibilityRay's ray an occluder counts (short of x itself).
inline constexpr double kPointRayEnd = 1.0 - 1e-5;

/// Flags in @p mask (one byte per pixel of @p view) the pixels whose centres may fall inside patch
/// @p patch (clipped to depth ≥ @p near) and @p margin pixels around them: what the coverage of that
/// patch reads from an item buffer (its centres and their 8 neighbours need margin ≥ 1).
void markProjection(const View& view, const Patch& patch, double near, int margin, std::vector<uint8_t>& mask);

// The solid angle and cosine-weighted solid angle of a patch (points, area vertices) are
// firstshot::analyticIntegral (common/table/firstshot_groups.h), shared with the .fsd reader.

/// Projected area of the polygon perpendicular to @p direction, m².
double unoccludedProjectedArea(const Vec3d& direction, const Vec3d* poly, int count);

// ---- What patchCoverage() sets up per (patch, view), for the GPU reduction (preprocess/gl/gl_reduce.h) ----

/// Patch @p patch in @p view as patchCoverage() tests it: its projection clipped to depth ≥ @p near
/// (q[0..n), image-plane units), the orientation that makes "inside" the same side of every edge, the
/// pixel box whose centres may fall inside, and the side of the patch's plane the eye is on.
struct CoverageSetup {
  Vec2d q[8];
  int n = 0;
  double sign = 1;
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  double eyeSide = 0;  ///< +1, −1, or 0 with the eye in the plane (orthographic: the view direction's side)
};
/// Fills @p out; false if no pixel centre of @p view can fall inside the patch (nothing to test).
bool coverageSetup(const View& view, const Patch& patch, double near, CoverageSetup& out);
/// The Newell normal (not unit) of a patch's double vertices, the plane its exact ray tests use.
Vec3d exactNormal(const Patch& patch);

}  // namespace firstshot
