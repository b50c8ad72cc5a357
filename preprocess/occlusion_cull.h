#pragma once
/// @file occlusion_cull.h
/// Which patches a full-window light sample need not visit (docs/preprocess-performance.md). The
/// analytic estimator examines every patch of the scene, not only those the item buffer shows, so
/// that patches narrower than a pixel are not lost (docs/firstshot-format.md, "Patches smaller than a
/// pixel"); a patch that shows nowhere is decided at its centroid (and, outside the window, at 4 more
/// points on it) by an exact ray from the eye. That is a ray per patch per sample: linear in
/// patches × samples, most of them for patches far behind walls.
///
/// The cull proves whole clusters of such patches hidden, in exact geometry: patches are grouped in
/// Morton order of their centroids (16 per cluster) and bounded by a sphere; a cluster is hidden
/// from eye e by a planar convex face F of the scene (a shape's own face, which its patches tile)
/// when the sphere lies beyond F's plane (e on the other side) and inside each plane through e and
/// an edge of F, with a margin. Then the segment from e to every point of every patch of the cluster
/// crosses F first, which is what the ray tests would find: such a patch gets no factor either way.
/// Candidate faces are those of the shapes the item buffer shows (the walls around the sample).
#include <cstdint>
#include <vector>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

class OcclusionCull {
 public:
  /// @p mesh's patches (their .shape index into @p scene.shapes); both must outlive the cull.
  OcclusionCull(const SceneDesc& scene, const PatchMesh& mesh, uint32_t clusterSize = 16);
  /// Appends to @p out the patches of every cluster not proven hidden from @p eye by a face of a
  /// shape that one of the patches @p shown belongs to (in cluster order, not sorted).
  void visible(const Vec3d& eye, const std::vector<uint32_t>& shown, std::vector<uint32_t>& out) const;
  size_t clusterCount() const { return clusters_.size(); }

 private:
  struct Face {
    Vec3d v[4];
    int count = 0;
    Vec3d n{0.0};  ///< unit normal
    double d = 0;  ///< plane: dot(n, x) = d
    Vec3d centroid{0.0};
  };
  struct Cluster {
    Vec3d centre{0.0};
    double radius = 0;
    uint32_t first = 0, count = 0;  ///< into order_
  };
  const PatchMesh& mesh_;
  std::vector<std::vector<Face>> faces_;  ///< per shape (empty: emissive, or too many faces to try)
  std::vector<Cluster> clusters_;
  std::vector<uint32_t> order_;  ///< patch IDs, cluster by cluster
  double margin_ = 0;            ///< absolute part of the margin, m
};

}  // namespace firstshot
