#pragma once
/// @file adaptive_mesh.h
/// The patch mesh as a forest of quadtrees: the uniform coarse mesh of settings.patch_size is the
/// roots, and a patch can be split into four (quads at their edge midpoints and centre, triangles at
/// their edge midpoints) down to settings.min_patch_size. Vertices stay in double precision from the
/// scene's own faces, so neighbours at the same level share vertices bit for bit; a split next to an
/// unsplit neighbour leaves a T-junction whose midpoint lies on the neighbour's edge (up to float
/// rounding of the patch vertices).
#include <cstdint>
#include <vector>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

class AdaptiveMesh {
 public:
  /// The coarse mesh: every non-emissive face split as buildPatches() does with @p patchSize.
  /// @throws InputError if there would be more than 2^32-1 patches.
  AdaptiveMesh(const SceneDesc& scene, double patchSize);

  /// The current leaves as a PatchMesh, in depth-first order of the roots (shape order, then face
  /// order, then the children of a split patch in place of it): the same scene, settings and split
  /// decisions give the same mesh byte for byte.
  const PatchMesh& mesh() const { return mesh_; }

  /// Whether leaf @p patch (an index into mesh()) may be split without an edge falling below @p minEdge (m).
  bool splittable(uint32_t patch, double minEdge) const;

  /// Splits the leaves flagged in @p split (one flag per current leaf) and rebuilds mesh().
  /// @return for every old leaf, the index of its first new leaf; a split leaf's 4 children follow
  /// each other from there, an unsplit leaf maps to one new leaf. Size: old leaf count + 1 (the
  /// last entry is the new leaf count).
  std::vector<uint32_t> split(const std::vector<uint8_t>& split);

  /// The children of a split patch: 4 polygons of @p count vertices (3 or 4), counter-clockwise as
  /// the parent; appended to @p out. The renderer finds a point's patch by this rule in the patch's own
  /// coordinates (render/scene/patch_locator.cpp, splitChild), and checks it on every table it reads.
  static void children(const Vec3d* v, int count, std::vector<std::vector<Vec3d>>& out);

  /// The lines that divide a split patch among its children, read from the 4 consecutive children
  /// @p c (as children() makes them): a quad's two midlines (edge midpoint to opposite edge
  /// midpoint; they cross at the centre), a triangle's three midlines. Line k runs from a[k] to
  /// b[k] on the parent's plane; ref[k] is a vertex of the parent on the side childOf() calls inside.
  struct SplitLines {
    int count = 0;  ///< 2 (quad) or 3 (triangle)
    Vec3d a[3], b[3], ref[3];
  };
  static SplitLines splitLines(const Patch* c);

  /// Which child (0–3) holds a point of the parent's plane, given for each of the @p lineCount
  /// lines of splitLines() whether the point lies on ref's side (@p inside, bit k for line k).
  static int childOf(int lineCount, unsigned inside);

 private:
  struct Leaf {
    Vec3d v[4];
    uint32_t count = 3, material = 0, shape = 0;
  };
  void rebuild();

  std::vector<Leaf> leaves_;
  PatchMesh mesh_;
  std::string file_;
};

}  // namespace firstshot
