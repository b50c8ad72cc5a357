#pragma once
/// @file item_buffer.h
/// Item buffers: for every pixel of a View, the ID of the patch seen through its centre.
/// Two interchangeable back ends implement ItemBufferRenderer: OpenGL (gl_item_buffer.h, rasterised
/// with OSMesa or EGL) and Embree (embree_item_buffer.h, one ray per pixel centre).
#include <cstdint>
#include <memory>
#include <vector>

#include "common/patches/patch_cutouts.h"
#include "common/patches/patches.h"
#include "common/util/math.h"
#include "preprocess/view.h"

namespace firstshot {

/// Background: no patch seen through the pixel.
inline constexpr uint32_t kNoPatch = 0xFFFFFFFFu;

/// What an item buffer renders: a triangle soup, each triangle carrying the full 32-bit ID of its patch.
/// Built from a PatchMesh (quads become the triangles (v0,v1,v2), (v0,v2,v3)); tests may build it
/// directly, e.g. to exercise IDs ≥ 2^24 without a mesh of 2^24 patches.
struct ItemGeometry {
  std::vector<Vec3> positions;    ///< 3 per triangle, world space (the patches' float vertices)
  std::vector<uint32_t> patchIds; ///< 1 per triangle; never kNoPatch
  Bounds3d bounds;                ///< of all positions
  /// Alpha cut-outs on the patches (null: none): the Embree back end sees through their holes (a filter),
  /// the GL back end refuses them.
  std::shared_ptr<const PatchCutouts> cutouts;

  size_t triangleCount() const { return patchIds.size(); }
  /// Appends one triangle.
  void addTriangle(const Vec3& a, const Vec3& b, const Vec3& c, uint32_t patchId);
  /// Triangles of every patch of @p mesh, patch ID = index in mesh.patches; with @p seeThrough (by
  /// material, non-empty), the patches of the materials it flags are left out: thin glass panes, which
  /// the item buffers see through (preprocess/pane_transmittance.h).
  static ItemGeometry fromPatches(const PatchMesh& mesh, const std::vector<uint8_t>& seeThrough = {});
};

/// Near plane used by both back ends: @p relative × the scene diagonal (1e-6 by default), so that a
/// patch 1e-4 of the scene size from the eye is still drawn.
double itemBufferNear(const Bounds3d& sceneBounds, double relative = 1e-6);

/// Renders item buffers of one fixed geometry.
///
/// Semantics shared by every back end: pixel (i, j) shows the closest triangle hit by the ray through
/// View::pixelCentre(i, j) with depth (distance along View::forward) in [near, far], where near is fixed
/// at construction and far = farDepth(view, scene bounds). Triangles are two-sided. IDs are written
/// row-major, row 0 at the top (see View). Pixels whose centre lies exactly on an edge shared by two
/// triangles may differ between back ends; nothing else may.
///
/// A renderer is not thread-safe: use one per worker thread.
class ItemBufferRenderer {
 public:
  virtual ~ItemBufferRenderer() = default;
  /// Fills @p ids (resized to view.width × view.height) with patch IDs, kNoPatch for background.
  virtual void render(const View& view, std::vector<uint32_t>& ids) = 0;
  /// Human-readable back end, e.g. "gl/osmesa" or "embree".
  virtual const char* name() const = 0;
  /// The near-plane depth in use.
  virtual double nearPlane() const = 0;
};

}  // namespace firstshot
