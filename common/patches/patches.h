#pragma once
/// @file patches.h
/// Splitting every non-emissive surface of the scene into small planar patches with stable IDs.
/// The patch mesh is what the preprocessor renders into item buffers and what the renderer traces,
/// so a hit's primitive maps straight to a patch.
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// A planar triangle or quad (vertices counter-clockwise seen from the normal side).
struct Patch {
  Vec3 v[4];          ///< v[3] unused for triangles
  uint32_t count = 3; ///< 3 or 4
  uint32_t material = 0;  ///< index into SceneDesc::materials
  uint32_t shape = 0;     ///< index into SceneDesc::shapes (the source surface)
  Vec3 normal{0, 0, 1};   ///< unit geometric normal, right-hand rule over the vertices
  Vec3 centroid{0.0f};    ///< area-weighted centroid
  double area = 0;        ///< m², computed in double from the exact (double) sub-polygon
};

/// A patch size (m) that leaves every face whole: one patch per scene face.
inline constexpr double kFacesAsTheyAre = std::numeric_limits<double>::infinity();

/// All patches; the index in @c patches is the patch ID (0..N-1, 32-bit).
struct PatchMesh {
  std::vector<Patch> patches;
  double patchSize = 0;  ///< the longest-edge bound the mesh was built with

  uint32_t size() const { return static_cast<uint32_t>(patches.size()); }
  /// Total area of all patches, m².
  double totalArea() const;
};

/// Area, normal and centroid of a planar polygon from its (float) vertices, computed in double.
void computePatchGeometry(Patch& p);
/// The same from the exact polygon @p exact (p.count vertices) the float vertices were rounded from.
void computePatchGeometry(Patch& p, const Vec3d* exact);

/// Splits a triangle or planar quad into sub-polygons whose edges are all at most @p maxEdge long.
/// Quads become an n×m grid of quads (bilinear split), triangles a k² regular subdivision.
/// Appends world-space polygons to @p out; vertices are shared exactly between neighbours.
void subdividePolygon(const Vec3d* v, int count, double maxEdge, std::vector<std::vector<Vec3d>>& out);

/// The grid subdividePolygon() cuts a polygon into: @p n cells along v0→v1 and @p m along v0→v3 of a quad, or
/// n = m = k along a triangle's edges (its k² similar triangles).
void polygonCells(const Vec3d* v, int count, double maxEdge, double& n, double& m);

/// How many pieces subdividePolygon() cuts the polygon into (a double: never overflows).
double subdivisionCount(const Vec3d* v, int count, double maxEdge);

/// Patches of the uniform mesh of @p patchSize over the non-emissive shapes, counted without building them.
double countPatchPolygons(const SceneDesc& scene, double patchSize);

/// Calls @p visit(shape index, polygon) for every polygon of the uniform mesh of @p patchSize over
/// the non-emissive shapes, in shape order then face order (what buildPatches() makes patches of).
/// @throws InputError if the count exceeds 2^32-1 or the patches cannot fit in physical memory
/// (common/util/memory_limit.h), before any is made.
void forEachPatchPolygon(const SceneDesc& scene, double patchSize,
                         const std::function<void(uint32_t, const std::vector<Vec3d>&)>& visit);

/// Builds the patch mesh of all non-emissive shapes, in shape order then face order, so the same
/// scene gives the same patches byte for byte. @throws InputError as forEachPatchPolygon().
PatchMesh buildPatches(const SceneDesc& scene, double patchSize);

/// Area of a shape's polygons, computed in double from its own vertices.
double shapeArea(const ShapeDesc& shape);

/// 64-bit hash of the patch data (vertices, materials, shapes), for determinism checks and file headers.
uint64_t hashPatches(const PatchMesh& mesh);

}  // namespace firstshot
