#pragma once
/// @file patch_cutouts.h
/// Alpha cut-outs on the patch mesh: leaves, fences, grilles, perforated shades. A material whose
/// alpha mode is mask or blend (MaterialDesc::alphaMode; docs/scene-format.md, "Cut-outs") is absent where its
/// alpha says so, for every ray of render/ and preprocess/: the ray tracers' filters (render/scene/
/// embree_cutout_filter.cpp, preprocess/embree_item_buffer.cpp) and the exact point tests of the preprocessor ask
/// PatchCutouts::exists at each candidate hit and reject it where the surface is absent.
///
/// Mask: the surface exists where alpha ≥ the cut-off. Blend: stochastic transparency, it exists with probability
/// alpha, decided by a hash of the ray and the patch (cutoutKey), so that the same ray always gets the same answer
/// and images do not depend on the thread count; every estimator that traces rays then sees a surface of
/// coverage alpha on average.
///
/// Which source face a patch lies in (for its texture coordinates) is found by common/patches/patch_faces.h, as for the
/// renderer's textures: the face of its shape that holds its centroid. Only cut-out patches are mapped; a scene without cut-outs
/// builds nothing (PatchCutouts::build returns null) and installs no filter.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// Checks material @p m's alpha (validateScene): cut-off and factor in [0, 1]; a cut-out only on a diffuse, glossy
/// or pbr material that does not emit. @throws InputError naming @p file and @p where (the material).
void validateCutout(const std::string& file, const std::string& where, const MaterialDesc& m);

/// A key for the ray from @p o in direction @p d meeting patch @p patch: the same ray and patch always give the
/// same key (the blend mode's coin).
uint64_t cutoutKey(const Vec3& o, const Vec3& d, uint32_t patch);

/// Whether a surface of material @p m with alpha @p alpha exists for the ray of key @p key: opaque always; mask
/// where alpha ≥ the cut-off; blend with probability alpha.
bool surfaceExists(const MaterialDesc& m, float alpha, uint64_t key);

class PatchCutouts {
 public:
  /// The cut-out patches of @p mesh (a patch mesh of @p scene; both must outlive the result), or null when no
  /// material of @p scene is a cut-out.
  static std::shared_ptr<const PatchCutouts> build(const SceneDesc& scene, const PatchMesh& mesh);

  /// Whether patch @p patch has a cut-out material (only those can be absent anywhere).
  bool cutout(uint32_t patch) const { return face_[patch] != kNoFace; }
  /// The alpha at point @p p of cut-out patch @p patch: the factor × the alpha texture at its texture coordinates
  /// (the texture's mean alpha when the shape has none), in [0, 1].
  float alphaAt(uint32_t patch, const Vec3d& p) const;
  /// The texture coordinates at point @p p of cut-out patch @p patch, before the alpha texture's transform, in
  /// @p uv; false (uv untouched) when its material has no alpha texture or its shape no texture coordinates, where
  /// alphaAt is the material's mean alpha (meanAlpha). The map is affine within each triangle of the patch's face.
  bool uvAt(uint32_t patch, const Vec3d& p, Vec2& uv) const;
  /// The alpha of a surface of material @p material without texture coordinates: the factor × its texture's mean.
  float meanAlpha(uint32_t material) const { return meanAlpha_[material]; }
  /// The material index of patch @p patch and the material itself.
  uint32_t materialOf(uint32_t patch) const { return mesh_->patches[patch].material; }
  const MaterialDesc& material(uint32_t patch) const { return scene_->materials[materialOf(patch)]; }
  /// Whether the surface exists at point @p p of patch @p patch for the ray of key @p key (true for a patch that
  /// is no cut-out).
  bool exists(uint32_t patch, const Vec3d& p, uint64_t key) const {
    return !cutout(patch) || surfaceExists(scene_->materials[mesh_->patches[patch].material], alphaAt(patch, p), key);
  }
  /// The expected coverage at point @p p of patch @p patch: 1 where a mask's alpha reaches the cut-off, else 0;
  /// a blend's alpha; 1 for a patch that is no cut-out. What a point sampled on the patch (not hit by a ray) weighs.
  float coverage(uint32_t patch, const Vec3d& p) const;
  /// The same for the ray from @p o in direction @p d (not necessarily unit) meeting the patch at parameter @p t.
  bool existsOnRay(uint32_t patch, const Vec3& o, const Vec3& d, float t) const {
    return !cutout(patch) || exists(patch, Vec3d(o) + double(t) * Vec3d(d), cutoutKey(o, d, patch));
  }

 private:
  static constexpr uint32_t kNoFace = 0xffffffffu;
  const SceneDesc* scene_ = nullptr;
  const PatchMesh* mesh_ = nullptr;
  std::vector<uint32_t> face_;      ///< by patch: the face of its shape it lies in, kNoFace if it is no cut-out
  std::vector<float> meanAlpha_;    ///< by material: alpha of a cut-out surface without texture coordinates
};

}  // namespace firstshot
