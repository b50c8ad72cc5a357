#pragma once
/// @file surface_textures.h
/// Textures on the traced patches: which source face each patch of a textured material lies in, the
/// texture coordinates of a point on it, and the surface there or averaged over the patch: the base colour
/// (albedo texture) and a pbr material's metallic and roughness (metallic-roughness texture).
///
/// Design: the renderer maps patches to source faces when it loads (common/patches/patch_faces.h), and the
/// first-shot table (.fsd) does not change. Only patches of textured materials are mapped: a scene without textures builds nothing and pays one branch
/// per hit (RenderScene::bsdfAt).
#include <cstdint>
#include <vector>

#include "common/patches/patch_faces.h"
#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// What the textures make of a surface at one point (or averaged over a patch).
struct SurfacePoint {
  Color albedo{0.0f};     ///< diffuse reflectance / base colour: the factor × the albedo texture, texel in [0, 1]
  float metallic = 0.0f;  ///< pbr: the factor × the metallic-roughness texture's B, clamped to [0, 1]
  float roughness = 0.0f; ///< pbr: the factor × its G, clamped to [0, 1]
};

// Laid out as ShadingNormals (shading_normals.h), a map of patches to faces, but of other data and lookups.
class SurfaceTextures {
 public:
  SurfaceTextures() = default;
  /// Maps the patches of @p mesh whose material has a texture to their faces in @p scene and averages the
  /// surface over each of them (in parallel; the same for any thread count).
  SurfaceTextures(const SceneDesc& scene, const PatchMesh& mesh);

  /// True when no material has a texture (nothing was built).
  bool empty() const { return face_.empty(); }
  /// Whether patch @p patch has a textured material.
  bool textured(uint32_t patch) const { return !empty() && face_[patch] != kNoFace; }
  /// Texture coordinates at point @p p on textured patch @p patch: the face's corner coordinates interpolated
  /// by @p p's barycentric coordinates in the face (a quad: in its triangle (0, 1, 2) or (0, 2, 3), exact for
  /// parallelograms mapped affinely, such as the built-in quads). (0, 0) when the shape has no coordinates.
  Vec2 uvAt(uint32_t patch, const Vec3& p) const;
  /// The surface at point @p p on textured patch @p patch: each texture looked up at uvAt (its mean when the
  /// shape has no coordinates) times its factor; a property without a texture is the material's own.
  SurfacePoint at(uint32_t patch, const Vec3& p) const;
  /// Diffuse reflectance at point @p p on textured patch @p patch: at(patch, p).albedo.
  Color albedoAt(uint32_t patch, const Vec3& p) const { return at(patch, p).albedo; }
  /// The surface of textured patch @p patch averaged over its area (8 × 8 stratified points, computed once).
  const SurfacePoint& patchSurface(uint32_t patch) const { return patchSurface_[patch]; }
  /// The albedo of textured patch @p patch averaged over its area.
  const Color& patchAlbedo(uint32_t patch) const { return patchSurface_[patch].albedo; }

 private:
  const SceneDesc* scene_ = nullptr;
  const PatchMesh* mesh_ = nullptr;
  std::vector<uint32_t> face_;        ///< by patch: the face of its shape it lies in, kNoFace if untextured
  std::vector<SurfacePoint> patchSurface_;  ///< by patch: the mean surface (textured patches only)
};

}  // namespace firstshot
