#pragma once
/// @file patch_locator.h
/// Which patch of a patch mesh holds a point of one of the scene's faces, so that the renderer traces the faces
/// themselves and still knows each hit's patch (EmbreeScene). A first-shot table cuts a Cornell box's 17 faces into
/// 25,000 patches, and a BVH over the patches takes more time per ray than one over the faces (docs/measurements.md,
/// "Tracing the faces").
///
/// Every patch is a sub-polygon of one face of its shape (common/patches/patch_faces.h): a cell of the face's uniform
/// grid (subdividePolygon at the mesh's patch size), or a piece of one (the preprocessor's adaptive refinement). A
/// query takes the point's grid coordinates on its face (a triangle's barycentric coordinates, a parallelogram's
/// affine ones, a planar quad's inverse bilinear ones), so its cell; a cell of one patch is that patch, a cell the
/// preprocessor split (AdaptiveMesh: four children at the edge midpoints, again and again) is descended by the point's
/// coordinates in it, halved at each split. A cell or face whose patches are neither (another patch size) keeps them
/// in a quadtree over the face's plane (leaves of at most kLeafPatches bounding boxes), whose leaf names the patch
/// that holds the point, or, on an edge or a rounding away from all of them, the one it lies least outside.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

class PatchLocator {
 public:
  /// Tracing the faces pays where the patches outnumber them by this much (the classroom's table: 1.28× its faces,
  /// traced as patches; a Cornell box's 180–1500×).
  static constexpr double kMinPatchesPerFace = 1.5;
  static constexpr uint32_t kLeafPatches = 8;  ///< a quadtree leaf holds at most this many (but at kMaxDepth)
  static constexpr int kMaxDepth = 12;

  /// The locator of @p patches (a patch mesh of @p scene) over the scene's faces, or null where tracing the patches
  /// is as good (fewer than kMinPatchesPerFace patches a face) or where the two do not match: a patch in no face,
  /// a face without a patch.
  static std::unique_ptr<const PatchLocator> build(const SceneDesc& scene, const PatchMesh& patches);

  /// What is traced: one polygon per face of the non-emissive shapes, in shape then face order (buildPatches with
  /// kFacesAsTheyAre).
  const PatchMesh& faces() const { return faces_; }
  /// The patch of face @p face (an index into faces()) that holds @p p, a point on its plane.
  uint32_t locate(uint32_t face, const Vec3& p) const;
  /// The patches of face @p face: patchesOf(face)[0 .. patchCount(face)).
  const uint32_t* patchesOf(uint32_t face) const { return &facePatches_[faceStart_[face]]; }
  uint32_t patchCount(uint32_t face) const { return faceStart_[face + 1] - faceStart_[face]; }
  /// How many faces are located through their grid (the others: one quadtree each), and how many cells through the
  /// preprocessor's refinement of them.
  uint32_t gridFaces() const { return gridFaces_; }
  uint32_t refinedCells() const { return refinedCells_; }

 private:
  enum class Kind : uint8_t { Whole, Triangle, Parallelogram, Bilinear };
  /// A face's grid: its point q (projected) has coordinates (s, t) = (m0 · (q − o), m1 · (q − o)) for a triangle or a
  /// parallelogram; a planar quad's are the inverse of q = o + s e + t f + s t g.
  struct Grid {
    Kind kind = Kind::Whole;
    uint8_t axis = 2;        ///< the axis its projection leaves out
    uint32_t n = 1, m = 1;   ///< cells along s and t (a triangle: n = m = k, two slots per (i, j))
    uint32_t cellBase = 0;   ///< its first entry in cells_
    Vec2 o{0.0f}, m0{0.0f}, m1{0.0f};
    Vec2d od{0.0}, e{0.0}, f{0.0}, g{0.0};  ///< a planar quad's (double: the quadratic's roots)
  };
  struct Node {
    Vec2 mid{0.0f};      ///< the split point; a point goes to child + (x > mid.x) + 2 (y > mid.y)
    uint32_t child = 0;  ///< the first of four children; 0: a leaf
    uint32_t first = 0, count = 0;  ///< a leaf's patches: leafPatches_[first .. first + count)
  };
  struct Flat {          ///< a patch in its face's plane
    Vec2 q[4];
    uint32_t count = 3;
    float sign = 1.0f;   ///< +1 if counter-clockwise in the projection, −1 if clockwise
  };
  /// An entry (of a cell, or a child of a split): a patch ID, kQuadtree | a quadtree's root node, or kSplit | a split
  /// (the preprocessor's refinement: four children at the edge midpoints, the cell's own coordinates halved).
  static constexpr uint32_t kTag = 0xc0000000u, kQuadtree = 0x80000000u, kSplit = 0xc0000000u;

  /// The grid coordinates of projected point @p q.
  static Vec2 gridCoords(const Grid& g, Vec2 q);
  /// The cell slot of grid coordinates @p st, and the point's coordinates in that cell in @p local: a quad cell's
  /// (u, v) ∈ [0, 1]², a triangle's (a, b) on (0, 0), (1, 0), (0, 1) (p = corner 0 + a (corner 1 − corner 0) + b …).
  static uint32_t cellOf(const Grid& g, Vec2 st, Vec2& local);
  /// Follows the splits from @p entry to the patch that holds the point of cell coordinates @p local.
  uint32_t descend(uint32_t entry, bool triangle, Vec2 local) const;
  /// The splits that place @p items (the patches of one cell of @p g) by the refinement's rule, or kTag where they do
  /// not tile the cell that way.
  uint32_t refinement(const Grid& g, const std::vector<uint32_t>& items);
  /// Fills nodes_[@p slot] with the quadtree of @p items over the box [@p lo, @p hi].
  void buildNode(uint32_t slot, std::vector<uint32_t>& items, Vec2 lo, Vec2 hi, int depth);
  uint32_t quadtree(std::vector<uint32_t>& items);
  uint32_t quadtreeLeaf(uint32_t face, uint32_t root, Vec2 q) const;
  /// How far @p p lies outside polygon @p fl, m; 0 inside (or on its boundary).
  static float outsideOf(const Flat& fl, Vec2 p);
  bool fillGrid(uint32_t face, const ShapeDesc& shape, const Face& sf, double patchSize);
  /// Patch @p j's mean corner, bounding box and area (m²) in its face's projection.
  Vec2 center(uint32_t j) const;
  void box(uint32_t j, Vec2& lo, Vec2& hi) const;
  double flatArea(uint32_t j) const;

  PatchMesh faces_;
  std::vector<uint32_t> faceStart_, facePatches_;  ///< patches grouped by face
  std::vector<Grid> grids_;                        ///< per face
  std::vector<uint32_t> cells_;                    ///< every face's cells' entries
  std::vector<Node> nodes_;
  std::vector<uint32_t> leafPatches_;
  std::vector<std::array<uint32_t, 4>> splits_;
  std::vector<Flat> flat_;                         ///< per patch
  uint32_t gridFaces_ = 0, refinedCells_ = 0;
};

}  // namespace firstshot
