#pragma once
/// @file embree_scene.h
/// The renderer's ray tracing: Embree 3 over the patch mesh (geometry 0, primitive = patch ID), or over the scene's
/// faces with a PatchLocator that finds each hit's patch, and the area-light triangles (one geometry per emitter).
/// This is the only place that knows Embree.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/materials/thin_glass.h"
#include "common/patches/patch_cutouts.h"
#include "common/patches/patches.h"
#include "common/util/math.h"
#include "render/scene/patch_locator.h"
#include "render/scene/ray.h"

namespace firstshot {

/// One area light's triangles in world space, counter-clockwise seen from the emitting side.
struct EmitterMesh {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> indices;  ///< three per triangle
  uint32_t triangleCount() const { return static_cast<uint32_t>(indices.size() / 3); }
};

/// The thin glass panes (common/materials/thin_glass.h) that transmittance() sees through: their optics, and which
/// pane each patch is. Empty: the scene has none, and transmittance() is occluded() (no filter, no cost).
struct GlassPatches {
  std::vector<ThinGlassBSDF> panes;
  std::vector<uint16_t> paneOfPatch;  ///< by patch ID: 0 opaque, k + 1 for panes[k]; empty when panes is
  bool empty() const { return panes.empty(); }
};

/// An immutable Embree scene. Queries are const and thread-safe.
class EmbreeScene {
 public:
  /// Builds the BVH over @p patches (triangles and planar quads) and @p emitters; @p glass the
  /// patches that are thin glass panes (for transmittance()); @p cutouts the alpha cut-outs every query sees
  /// through (render/scene/embree_cutout_filter.h; null: none, no filter), kept alive by the scene. With
  /// @p locator (built over @p patches), the BVH holds its faces instead, and a hit's patch is the one that holds
  /// the hit point: the same hits, through fewer primitives (not with cut-outs, whose filter works by patch).
  /// @throws std::runtime_error if Embree fails; std::logic_error for a locator with cut-outs.
  EmbreeScene(const PatchMesh& patches, const std::vector<EmitterMesh>& emitters, GlassPatches glass = {},
              std::shared_ptr<const PatchCutouts> cutouts = nullptr,
              std::shared_ptr<const PatchLocator> locator = nullptr);
  /// Whether the faces are traced (a PatchLocator finds the patches), and how many polygons the BVH holds.
  bool tracesFaces() const;
  size_t tracedPolygons() const;
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Closest hit in [ray.tmin, ray.tmax]; fills @p hit and returns true, or returns false.
  bool intersect(const Ray& ray, Hit& hit) const;
  /// The closest hits of up to 16 coherent rays (the camera rays of a 4 × 4 pixel block) as two
  /// Embree packets of 8 (k < 8, k ≥ 8): rays[k] for the k < @p count with active[k]; found[k] says
  /// whether hits[k] was filled (false for the inactive ones). Each hit is a closest hit as
  /// intersect() gives it; where two primitives tie at exactly the same t (a shared edge), which one
  /// is reported may differ from intersect() and may depend on the packet's other rays.
  /// Packets of 8, not one of 16: rtcIntersect16 runs Embree's AVX-512 kernels, and the clock drop
  /// that follows them slowed the whole path tracer (+1.5% rays/s against +8%, bench_render).
  void intersect16(const Ray* rays, const bool* active, int count, Hit* hits, bool* found) const;
  /// True if anything lies on the ray within [ray.tmin, ray.tmax].
  bool occluded(const Ray& ray) const;
  /// The fraction of light that crosses the segment [ray.tmin, ray.tmax]: 0 if an opaque
  /// surface lies on it, else the product of T(θ) of the thin glass panes it crosses (1 for none). One
  /// occlusion traversal whose context filter multiplies each pane's T(θ) and rejects the hit (a pane
  /// met twice at the same distance, on a quad's diagonal or the edge two patches share, counts once);
  /// an opaque hit ends it. Without glass it is occluded().
  Color transmittance(const Ray& ray) const;
  /// True if the scene has thin glass (transmittance() may be neither 0 nor 1).
  bool hasGlass() const;
  /// Every surface the ray crosses within [ray.tmin, ray.tmax], sorted by t, appended to @p out: one
  /// traversal whose context filter records each candidate and rejects it (a hit found twice, e.g.
  /// on a quad's diagonal, is listed once). The ray bundles' alternative to successive closest hits.
  void allHits(const Ray& ray, std::vector<Hit>& out) const;

  /// Benchmark hook: plain incoherent rtcIntersect1 calls over @p rays, nothing else.
  /// @return the number of rays that hit something.
  size_t intersectRaw(const Ray* rays, size_t count) const;
  /// Benchmark hooks for ray layouts: the same closest-hit queries as intersectRaw, traced as
  /// Embree packets of 16 (rtcIntersect16, rays taken 16 at a time in order) or as one stream
  /// (rtcIntersect1M), both flagged coherent. @return the number of rays that hit something.
  size_t intersectRawPackets(const Ray* rays, size_t count) const;
  size_t intersectRawStream(const Ray* rays, size_t count) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Sets flush-to-zero and denormals-are-zero for the calling thread (Embree's recommendation;
/// call it at the start of every worker task). No-op on CPUs without SSE.
void enableFlushToZero();

}  // namespace firstshot
