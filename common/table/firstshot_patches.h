#pragma once
/// @file firstshot_patches.h
/// Packed patches: the compact on-disk form of a patch mesh (docs/firstshot-format.md, section PTCH,
/// version 4). Lossless: unpacking gives back every patch bit for bit.
///
/// Neighbouring patches share their corners exactly (common/patches/patches.h), so the corners are stored
/// once in a vertex pool and each patch keeps 3 or 4 indices into it; the (shape, material) pairs
/// come in runs of consecutive patches. A triangle then costs 45 bytes plus its share of the pool
/// (about 6 for a closed mesh) where version 3 spent 92.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/patches/patches.h"

namespace firstshot {

/// The PTCH section's arrays (version 4).
struct PackedPatches {
  std::vector<Vec3> vertices;         ///< the distinct corners (bit patterns), in order of first use
  std::vector<uint32_t> runShape;     ///< per run of consecutive patches: their SceneDesc shape
  std::vector<uint32_t> runMaterial;  ///< ... their material
  std::vector<uint32_t> runLength;    ///< ... how many patches the run holds (≥ 1)
  std::vector<uint8_t> corners;       ///< per patch: 3 or 4
  std::vector<uint32_t> index;        ///< per patch, its corners' indices into @c vertices (Σ corners)
  std::vector<Vec3> normal;           ///< per patch, as in Patch
  std::vector<Vec3> centroid;         ///< per patch, as in Patch
  std::vector<double> area;           ///< per patch, m², as in Patch
};

/// Packs @p mesh's patches (not its patch size).
PackedPatches packPatches(const PatchMesh& mesh);

/// Rebuilds @p mesh's patches from @p p (a triangle's unused 4th corner repeats its 3rd, as every
/// patch builder leaves it). Every inconsistency (runs or corner counts that do not add up, a corner
/// count other than 3 or 4, an index outside the pool, an area not positive) is reported by @p fail
/// with a message; fail must not return.
void unpackPatches(const PackedPatches& p, PatchMesh& mesh, const std::function<void(const std::string&)>& fail);

}  // namespace firstshot
