#pragma once
/// @file embree_item_buffer.h
/// The Embree 3 item-buffer back end: one ray per pixel centre, origin View::pixelOrigin, direction
/// View::pixelDirection (forward component 1, so the ray parameter is the depth and tnear/tfar are the
/// GL back end's near/far planes). Triangles are two-sided (no culling); the scene is built with
/// RTC_SCENE_FLAG_ROBUST so that rays through shared edges never slip between two triangles.
/// Ray origins are rounded to float (Embree's ray format), i.e. by ≤ half an ulp of the eye coordinates.
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "preprocess/item_buffer.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace firstshot {

/// How rays are traced (for benchmarking; all give identical results).
enum class EmbreeRayMode { Single, Packet8, Packet16, Stream };

class EmbreeItemBuffer final : public ItemBufferRenderer {
 public:
  /// Builds the BVH once. @p robust: Embree's watertight mode (RTC_SCENE_FLAG_ROBUST), which item
  /// buffers and exact point tests need (no ray slips through the edge two triangles share); false
  /// traces about a third faster, for votes that one ray more or less does not decide (the
  /// exposure probes). @throws std::runtime_error on Embree errors.
  EmbreeItemBuffer(const ItemGeometry& geometry, const Bounds3d& sceneBounds, double nearRelative = 1e-6,
                   EmbreeRayMode mode = EmbreeRayMode::Packet16, bool robust = true);
  EmbreeItemBuffer(const PatchMesh& mesh, const Bounds3d& sceneBounds, double nearRelative = 1e-6,
                   EmbreeRayMode mode = EmbreeRayMode::Packet16);
  ~EmbreeItemBuffer() override;
  EmbreeItemBuffer(const EmbreeItemBuffer&) = delete;
  EmbreeItemBuffer& operator=(const EmbreeItemBuffer&) = delete;

  /// Traces on the calling thread with FTZ/DAZ on (the thread's MXCSR is restored afterwards).
  /// Only reads the scene, so it may also be called from several threads at once.
  void render(const View& view, std::vector<uint32_t>& ids) override;
  const char* name() const override { return "embree"; }
  /// The item buffer of @p view at the pixels flagged in @p mask (row-major, one byte per pixel,
  /// View's pixel order) only; every other pixel is kNoPatch. Thread-safe, like render(). For
  /// refinement passes, which need the pixels around a few split patches.
  void renderMasked(const View& view, const std::vector<uint8_t>& mask, std::vector<uint32_t>& ids) const;
  /// The patch first hit by the ray @p origin + t·@p direction, t in [0, @p tfar] (direction not
  /// necessarily unit), or kNoPatch; @p t receives its t. Thread-safe, like render().
  uint32_t firstHit(const Vec3d& origin, const Vec3d& direction, double tfar, double& t) const;
  /// Whether any patch meets the ray @p origin + t·@p direction, t in [0, @p tfar]: firstHit() != kNoPatch, by an
  /// occlusion query (it stops at the first surface found, not the nearest). Thread-safe, like render().
  bool occluded(const Vec3d& origin, const Vec3d& direction, double tfar) const;
  /// firstHit() of @p n ≤ 8 rays from @p origin along @p directions[k], t in [0, ∞), into @p out[k] (a patch or
  /// kNoPatch), traced as one packet. Thread-safe, like render().
  void firstHits(const Vec3d& origin, const Vec3d* directions, size_t n, uint32_t* out) const;
  /// occluded() of @p n rays at once (@p origins[k] + t·@p directions[k], t in [0, @p tfar]) into @p out[k] (1:
  /// occluded), traced in packets of 16: the same answers, faster for coherent rays (a directional light's point
  /// tests). Thread-safe, like render().
  void occluded(const Vec3d* origins, const Vec3d* directions, double tfar, size_t n, uint8_t* out) const;
  /// Calls @p test(patch) with the patch of every triangle whose bounding box may meet the ball of radius @p radius
  /// about @p centre (Embree's point query: a superset of those that do, some patches more than once), until it
  /// returns true. @return whether it did. Thread-safe, like render().
  bool anyPatchNear(const Vec3& centre, float radius, const std::function<bool(uint32_t)>& test) const;
  double nearPlane() const override { return near_; }
  void setRayMode(EmbreeRayMode mode) { mode_ = mode; }

 private:
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  std::vector<uint32_t> triPatch_;  ///< primID -> patch ID
  Bounds3d bounds_;
  double near_ = 0;
  EmbreeRayMode mode_ = EmbreeRayMode::Packet16;
  /// Alpha cut-outs (ItemGeometry::cutouts) and what their filter reads (null: no filter installed).
  std::shared_ptr<const PatchCutouts> cutouts_;
  std::pair<const PatchCutouts*, const uint32_t*> cutoutFilter_{nullptr, nullptr};  ///< the filter's user data

 public:
  /// The alpha cut-outs these rays see through, or nullptr.
  const PatchCutouts* cutouts() const { return cutouts_.get(); }
};

}  // namespace firstshot
