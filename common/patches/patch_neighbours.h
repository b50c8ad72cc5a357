#pragma once
/// @file patch_neighbours.h
/// Which patches touch which: the pairs whose axis-aligned bounding boxes overlap once grown by
/// 10⁻⁵ of the mesh's diagonal (shared edges and corners, T-junctions of adaptive meshes, and
/// surfaces that meet or cross each other). A superset of the patches that share a point, never
/// fewer; the first-shot renderer's table visibility relies on that, and the preprocessor's burial test
/// (preprocess/exposure.h) takes the same grown boxes (grownPatchBoxes).
#include <cstdint>
#include <vector>

#include "common/patches/patches.h"

namespace firstshot {

/// A patch's axis-aligned bounding box grown by 10⁻⁵ of the mesh's diagonal, m: two patches touch where theirs overlap.
struct GrownBox {
  Vec3 lo{0.0f}, hi{0.0f};
  bool overlaps(const GrownBox& b) const {  // (& rather than &&: no branches)
    return (lo.x <= b.hi.x) & (b.lo.x <= hi.x) & (lo.y <= b.hi.y) & (b.lo.y <= hi.y) & (lo.z <= b.hi.z) & (b.lo.z <= hi.z);
  }
};

/// The grown boxes of the patches of @p mesh, by patch; @p grow receives how far each side was moved out, m.
std::vector<GrownBox> grownPatchBoxes(const PatchMesh& mesh, float& grow);

/// CSR over the patches of @p mesh: the neighbours of patch j are adjacent[start[j]..start[j+1]),
/// ascending, j itself left out.
struct PatchNeighbours {
  std::vector<uint64_t> start;
  std::vector<uint32_t> adjacent;
};

/// The neighbours of every patch of @p mesh (a uniform grid of cells three times the median patch
/// size proposes the pairs, each cell's patches tested pair by pair once; built in parallel).
PatchNeighbours patchNeighbours(const PatchMesh& mesh);

}  // namespace firstshot
