#pragma once
/// @file patch_faces.h
/// Which source face of its shape each traced patch lies in, and where a point lies in that face: what the
/// per-point surface data of the source faces (texture coordinates, render/scene/surface_textures.h; shading normals,
/// render/scene/shading_normals.h) is interpolated by.
///
/// Every patch, of the uniform split or of the preprocessor's adaptive quadtrees, is a sub-polygon of one face of
/// its shape (Patch::shape), so that face is the one that holds the patch's centroid; the search walks the shape's
/// faces from the previous patch's face, and since patches come in face order it is linear in practice.
#include <cstdint>
#include <functional>
#include <vector>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

inline constexpr uint32_t kNoFace = 0xffffffffu;

/// The triangle of a face that holds a point: corners (0, 1, 2), or (0, 2, 3) of a quad when the point lies beyond
/// the diagonal 0–2, with the point's barycentric coordinates (β, γ) in it: p ≈ c0 + β(c1 − c0) + γ(c2 − c0).
struct FaceTriangle {
  int corner[3] = {0, 1, 2};
  Vec2d bary{0.0};
  /// The corner attribute @p at(k) (k a corner of the face) interpolated at the point.
  template <typename T, typename At>
  T interpolate(const At& at) const {
    const T a = at(corner[0]), b = at(corner[1]), c = at(corner[2]);
    return a + float(bary.x) * (b - a) + float(bary.y) * (c - a);
  }
};

/// The triangle of face @p f of shape @p s that holds @p p (projected onto its plane), and p's coordinates in it.
FaceTriangle faceTriangle(const ShapeDesc& s, const Face& f, const Vec3d& p);

/// For each patch of @p mesh for which @p wanted(patch) holds, the index of the face of its shape that holds it;
/// kNoFace for the others.
std::vector<uint32_t> mapPatchesToFaces(const SceneDesc& scene, const PatchMesh& mesh,
                                        const std::function<bool(const Patch&)>& wanted);

}  // namespace firstshot
