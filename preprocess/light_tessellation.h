#pragma once
/// @file light_tessellation.h
/// Splitting an area light into the triangles whose vertices become light samples: uniformly (an
/// explicit edge length) or automatically, as finely as the receivers in front of the light need for
/// a stated relative accuracy of the vertex rule.
///
/// The renderer integrates an area light with the vertex rule: each triangle T of the tessellation
/// contributes (A_T/3)·Σ_corners f(y), f(y) = Le·cosθ_x·cosθ_L/|x−y|². Its error at a receiver point x
/// is the sum of the triangles' own errors, and for a triangle of diameter h at distance d from x
///     |error_T| ≤ C·(h/d)²·E_T     (E_T: the exact irradiance T gives at x),
/// so a tessellation in which every triangle satisfies C·(h/d)² ≤ tolerance, d being its distance to
/// the nearest receiver surface in front of the light, keeps the relative error within the tolerance
/// at every receiver point that sees the whole light above its horizon. C = kVertexRuleErrorConstant,
/// measured (docs/firstshot-format.md, "Light samples"): over random receivers facing the triangle
/// within 60°, h/d ≤ 1.6, max |error_T|/(E_T·(h/d)²) is 0.65–0.88 for squares, 1.24:1 rectangles and
/// equilateral, right and thin triangles (1.1 for 4:1 rectangles, median 0.2–0.35); for any
/// orientation with the triangle in front, |error_T| ≤ 0.5·(h/d)²·A_T/d². Where a receiver's plane cuts
/// the light the integrand has a kink and the relative error is larger, on a small irradiance.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// C of the vertex rule's per-triangle bound |error| ≤ C·(h/d)²·E (see the file comment).
inline constexpr double kVertexRuleErrorConstant = 1.0;

/// Automatic tessellation: the first grid of a face has at least this many cells along its longest
/// extent when its receivers are close (further splits are adaptive).
inline constexpr int kLightGridMaxCells = 8;

/// Automatic tessellation floor: no triangle is split below (face diameter)/kLightMinSizeRatio, m. A
/// receiver touching the light therefore gets at most 3 adaptive levels below the 8×8 first grid
/// (≤ 64² cells per face) and the bound is not met in the region within ~10 floor sizes of it.
inline constexpr double kLightMinSizeRatio = 64.0;

/// Automatic tessellation budget: an area light that would take more samples than this (a receiver
/// touching it: a lamp's bowl, a shelf; a large light near a wall) is cut again with the tolerance
/// doubled twice, then the floor raised to 1/8 of a face, the tolerance doubled twice more and the
/// floor raised to the whole face, until it fits (one line on stderr says what it reached). Each
/// sample costs the preprocessor an item-buffer render.
inline constexpr size_t kLightSampleBudget = 256;
/// No budget: the tolerance and floor as asked, however many samples they take (tests, the accuracy bench).
inline constexpr size_t kNoLightSampleBudget = ~size_t(0);

/// Automatic tessellation of an emissive shape of more faces than this: its samples are merged into
/// clusters as its receivers allow (preprocess/light_clusters.h), so their count follows the need,
/// not the mesh.
inline constexpr size_t kLightMeshFaces = 16;

/// A tessellated area light: vertex samples with their trapezoidal weights, and the triangles.
struct LightTessellation {
  std::vector<Vec3d> positions;              ///< sample positions, m, in order of first appearance
  std::vector<double> weights;               ///< S_i/3, m² (S_i: area of the triangles around vertex i)
  std::vector<Vec3d> normals;                ///< unit, area-weighted normal of the triangles around it
  std::vector<std::array<Vec3d, 3>> triangles;  ///< the leaf triangles, m (counter-clockwise from the front)
  /// An emitter with an emission texture (common/materials/emission_texture.h): each sample's radiance
  /// ∫ Le φ_i dA / ∫ φ_i dA, W/(m² sr) (φ_i its hat function over the leaf triangles around it, ∫ φ_i dA its
  /// weight), so that Σ weight·emission is the light's ∫ Le dA and a sample under a bright part of the texture
  /// emits more.
  /// Empty: the material's emission for every sample.
  std::vector<Color> emission;
  double floorRatio = 0;  ///< automatic: no cell split below (face diameter)/floorRatio (kLightMinSizeRatio unless the budget raised it)
  double tolerance = 0;   ///< automatic: the tolerance met (light_tolerance unless the budget relaxed it)
};

/// Distance (m) from @p p to a convex planar polygon of @p count ≤ 8 vertices.
double pointPolygonDistance(const Vec3d& p, const Vec3d* poly, int count);

/// Distance (m) between two convex planar polygons (≤ 8 vertices each) that do not cross each
/// other's interior: the least of the vertex-to-polygon and edge-to-edge distances.
double polygonPolygonDistance(const Vec3d* a, int na, const Vec3d* b, int nb);

/// The receivers of one emissive face: every face of every non-emissive shape, clipped to the
/// half-space in front of the face's plane (the side its normal points to). Faces behind the light,
/// and faces lying in its plane (which it cannot light), are left out.
class LightReceivers {
 public:
  /// @param scene all shapes; @param origin a point of the emitting face's plane; @param normal its
  /// front normal (any length).
  LightReceivers(const SceneDesc& scene, const Vec3d& origin, const Vec3d& normal);
  /// Distance (m) from the convex polygon @p poly (in the light's plane) to the nearest receiver;
  /// +∞ when there is none.
  double distance(const Vec3d* poly, int count) const;
  /// Number of receiver polygons kept.
  size_t size() const { return polys_.size(); }

 private:
  struct Poly {
    std::array<Vec3d, 8> v;
    int count = 0;
    Vec3d centre{0.0};
    double radius = 0;  ///< bounding sphere about centre, m
  };
  std::vector<Poly> polys_;
};

/// Tessellates the emissive shape @p shapeIndex. @p lightPatchSize > 0: uniform, every edge at most
/// that long (m; quads as grids, triangles k²-split). Otherwise automatic with relative accuracy
/// @p tolerance: each face is cut into a grid whose cells meet the bound at the face's own distance
/// to its receivers (at least (diameter)/kLightGridMaxCells cells), then each cell is split 4-way
/// (midpoints; quads bilinearly) until C·(h/d)² ≤ tolerance, h its diameter and d its distance to
/// the receivers, or h reaches the floor (floor, then tolerance, relaxed while the samples exceed
/// @p budget); an emissive mesh's samples are then merged (preprocess/light_clusters.h). Vertices are shared exactly between neighbours; hanging
/// vertices where levels meet get weight only from their own triangles, so Σ weights = area.
/// Same input → same output, byte for byte. Says on stderr what the budget relaxed, if anything, unless
/// @p quiet (reportRelaxed).
LightTessellation tessellateAreaLight(const SceneDesc& scene, int shapeIndex, double lightPatchSize, double tolerance,
                                      size_t budget = kLightSampleBudget, bool quiet = false);

/// One stderr line for an automatic tessellation @p t of shape @p shapeIndex whose tolerance or floor the
/// budget relaxed from @p asked; nothing when it did not.
void reportRelaxed(const SceneDesc& scene, int shapeIndex, const LightTessellation& t, double asked,
                   size_t budget = kLightSampleBudget);

/// Worst error of the vertex rule Σ w_i cosθ_x cosθ_L / d² of @p t against the exact
/// ∫ cosθ_x cosθ_L / d² dA (analytic::polygonCosineSolidAngle) over @p points (position, normal), the
/// light being the single-face emissive shape @p light. Points behind the light, or that receive
/// nothing, are skipped. For tests and the accuracy bench.
struct VertexRuleError {
  double uncut = 0;  ///< relative, at points that see the whole light above their horizon
  double cut = 0;    ///< at points whose plane cuts the light: |error| / Σ w_i cosθ_L/d² (the point facing the light)
};
VertexRuleError vertexRuleError(const ShapeDesc& light, const LightTessellation& t,
                                const std::vector<std::pair<Vec3d, Vec3d>>& points);

}  // namespace firstshot
