#pragma once
/// @file shading_normals.h
/// Shading normals on the traced patches: the normal a BSDF is evaluated about at a point, from the
/// source face's corner normals (a mesh file's NORMAL / vn, a "smooth" sphere) interpolated by the point's
/// barycentric coordinates, then perturbed by the material's tangent-space normal map.
///
/// The tangent frame is the file's where it gives one (glTF's TANGENT, ShapeDesc::tangents: the corners' tangents
/// and bitangents w·N×T interpolated, T made orthogonal to the interpolated normal n and B = ±n × T on the side of
/// the file's bitangent). Otherwise it is generated per triangle from its texture coordinates: the
/// tangent T = ∂p/∂u and the image's up direction −∂p/∂v (glTF's v points down) solved from the triangle's edges
/// and uv differences, T made orthogonal to the interpolated normal n (Gram–Schmidt) and the bitangent
/// B = ±n × T, its sign the handedness of the mapping (mirrored uv islands). MikkTSpace, with which normal maps
/// are usually baked, differs in averaging T over the triangles that share a vertex (a tangent field continuous
/// across edges); ours is constant over a triangle, so a map baked with MikkTSpace on a curved, coarsely
/// tessellated mesh shows small steps at its edges (none on planar parts or where uv is affine across edges).
/// The texel t (linear, not sRGB) gives n' = normalize((2t_x − 1)·s·T + (2t_y − 1)·s·B + (2t_z − 1)·n), s the
/// material's normal scale.
///
/// The result is always on the front side of the geometric normal ng (the face's winding decides the front: a
/// corner normal behind it is turned, and a perturbed normal that falls behind it is dropped). Only patches with
/// corner normals or a normal map (with texture coordinates) are mapped to faces: a scene without either builds
/// nothing and pays one branch per hit (RenderScene::shadingNormal).
///
/// Particle (importance) paths need Veach's adjoint correction for shading normals (thesis §5.3):
/// f*(ω_prev → ω_next) = f · |ω_prev·n_s| |ω_next·n_g| / (|ω_prev·n_g| |ω_next·n_s|), ω_prev towards where the
/// particle came from; adjointCorrection() is that factor.
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/patches/patch_faces.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

class ShadingNormals {
 public:
  ShadingNormals() = default;
  /// Maps the patches of @p mesh whose shape has normals or whose material has a normal map to their faces.
  ShadingNormals(const SceneDesc& scene, const PatchMesh& mesh);

  /// True when no patch has a shading normal (nothing was built).
  bool empty() const { return face_.empty(); }
  /// Whether patch @p patch may have a shading normal other than its geometric one.
  bool shaded(uint32_t patch) const { return !empty() && face_[patch] != kNoFace; }
  /// The unit shading normal at point @p p of shaded patch @p patch whose geometric normal is @p ng (unit):
  /// dot(result, ng) > 0.
  Vec3 normalAt(uint32_t patch, const Vec3& p, const Vec3& ng) const;

 private:
  const SceneDesc* scene_ = nullptr;
  const PatchMesh* mesh_ = nullptr;
  std::vector<uint32_t> face_;  ///< by patch: the face of its shape it lies in, kNoFace if unshaded
};

/// Veach's adjoint factor |ω_prev·ns| |ω_next·ng| / (|ω_prev·ng| |ω_next·ns|) that turns f into the BSDF a particle
/// (importance) path scatters with, for unit world directions @p wPrev (towards where it came from) and @p wNext
/// (where it goes), shading normal @p ns and geometric normal @p ng; 0 where a denominator is 0.
inline float adjointCorrection(const Vec3& wPrev, const Vec3& wNext, const Vec3& ns, const Vec3& ng) {
  const float den = std::abs(glm::dot(wPrev, ng)) * std::abs(glm::dot(wNext, ns));
  return den > 0.0f ? std::abs(glm::dot(wPrev, ns)) * std::abs(glm::dot(wNext, ng)) / den : 0.0f;
}

}  // namespace firstshot
