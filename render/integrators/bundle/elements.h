#pragma once
/// @file elements.h
/// The surfaces a ray bundle exchanges radiance between: every patch of the traced mesh (element
/// j = patch j) followed by every triangle of the area-light meshes (so an emitter with a non-zero
/// albedo reflects like a patch). Each element keeps one incoming-radiance value per side.
#include <cstdint>
#include <vector>

#include "common/util/math.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// One planar element of the bundle's state.
struct BundleElement {
  Vec3 normal{0.0f, 0.0f, 1.0f};  ///< unit geometric normal of the front side (side 0)
  float area = 0.0f;              ///< m²
  uint32_t material = 0;          ///< index into the scene's materials
  uint32_t light = kNoId;         ///< area light (LightSet index) of an emitter triangle; kNoId for a patch
};

class BundleElements {
 public:
  /// Lists the patches and emitter triangles of @p scene and its bounding sphere.
  void build(const RenderScene& scene);

  uint32_t size() const { return uint32_t(elements_.size()); }
  const BundleElement& operator[](uint32_t e) const { return elements_[e]; }
  /// The element a hit lies on.
  uint32_t index(const Hit& hit) const {
    return hit.onPatch() ? hit.patch : emitterBase_[hit.emitter] + hit.triangle;
  }
  /// Bounding sphere of all surfaces: centre and radius, m (radius > 0).
  const Vec3& center() const { return center_; }
  float radius() const { return radius_; }

 private:
  std::vector<BundleElement> elements_;
  std::vector<uint32_t> emitterBase_;  ///< by emitter mesh: its first element
  Vec3 center_{0.0f};
  float radius_ = 1.0f;
};

}  // namespace firstshot
