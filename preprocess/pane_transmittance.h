#pragma once
/// @file pane_transmittance.h
/// The thin glass panes between a light sample and a patch. The item buffers leave the panes
/// out (ItemGeometry::fromPatches with the panes' materials: neither back end draws them, and no exact
/// point test meets them), so a patch behind a window gets the factor it would get without the glass;
/// the preprocessor then multiplies each factor r_ij by the panes' transmittance T(θ) along the ray from
/// sample i to the centroid of patch j (luminance of the product over the panes it crosses: a table's
/// factors are grey, so a tinted pane's colour is lost for the replaced lights; docs/scene-format.md).
/// One ray per factor, on a BVH of the panes alone; nothing at all for a scene without thin glass.
/// What it does not resolve: a patch partly behind a pane and partly not takes the value at its centroid
/// (the opening a pane fills is cut by the opaque wall around it, whose shadow edge refinement follows).
#include <cstdint>
#include <memory>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// Per material: 1 for a thin glass pane (the item buffers leave its patches out), else 0; empty when
/// the scene has none.
std::vector<uint8_t> seeThroughMaterials(const SceneDesc& scene);

// Non-copyable over a private Impl, as ParticleScene (luminaire_trace.h): the usual shape, no shared logic.
class PaneTransmittance {
 public:
  /// A BVH over the faces of @p scene's thin glass shapes (none: empty(), and nothing is built).
  explicit PaneTransmittance(const SceneDesc& scene);
  ~PaneTransmittance();
  PaneTransmittance(const PaneTransmittance&) = delete;
  PaneTransmittance& operator=(const PaneTransmittance&) = delete;

  bool empty() const { return !impl_; }
  /// Luminance of Π T(θ) over the panes the segment from @p a to @p b crosses (1 for none).
  double between(const Vec3d& a, const Vec3d& b) const;
  /// The same along the ray from @p a in the unit direction @p d, to infinity (a directional light).
  double toward(const Vec3d& a, const Vec3d& d) const;

 private:
  double along(const Vec3d& o, const Vec3d& d, double tfar) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace firstshot
