#pragma once
/// @file exposure.h
/// Points of a patch buried inside closed objects: the floor under a box standing on it, the wall
/// behind a partition built against it. No ray from the rest of the scene reaches them, so the
/// renderer never shades them; a visible fraction that counted them as lit area that happens to be
/// occluded would darken the exposed rest of the patch (the first-shot term at x is V_ij × the
/// unoccluded irradiance at x, render/firstshot/lighting.h). The analytic estimator therefore takes the
/// visible fraction over the exposed part of a patch only (preprocess/coverage.h).
///
/// Test (the rule of lightmap bakers): a point is buried on one side of its patch when most of the
/// rays leaving it over that side's hemisphere hit the back face of a patch (the side its normal
/// points away from); surfaces of closed objects face outwards. Each patch side is probed at a
/// grid of points, on first use.
///
/// Only another surface that meets or crosses a patch can bury part of it (a closed object's faces
/// bound what it buries; a patch buried whole keeps no mask). A patch that touches nothing but
/// coplanar patches (touching as common/patches/patch_neighbours.h has it: bounding boxes grown by 10⁻⁵ of the
/// diagonal overlap; found with a point query of the probes' BVH), which its hemisphere rays never hit, is
/// therefore decided without probes: its mask is not partial.
///
/// A point is decided at the centre of its cell of a lattice in the patch's plane (kLatticePerStep
/// cells per grid step), once per cell: by the nearest probe point, or, when that point is on the
/// border between buried and exposed probes, by probing the cell centre itself. The pixel centres
/// of every light sample that sees the patch fall on the same cells, so each cell is decided once,
/// and the answer does not depend on which light or which thread asked first.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "common/patches/patch_neighbours.h"
#include "common/patches/patches.h"
#include "common/util/math.h"
#include "preprocess/embree_item_buffer.h"

namespace firstshot {

/// Probe points of one side of a patch and which of them are buried.
struct ExposureMask {
  std::vector<Vec3d> points;    ///< world positions on the patch, m
  std::vector<uint8_t> buried;  ///< 1 if the point is buried
  std::vector<uint8_t> border;  ///< 1 if a probe about one grid step away disagrees
  /// True when some points are buried and some are not (otherwise the mask changes nothing: a
  /// patch buried whole is never shaded, and a wrongly oriented surface must not blank a patch).
  bool partial = false;
  /// Lattice (partial masks only): cell (i, j) has its centre at
  /// origin + (i + ½) h s + (j + ½) h t, on the patch's plane.
  Vec3d origin{0.0}, s{0.0}, t{0.0};
  double h = 0;                                  ///< cell size, m
  int nu = 0, nv = 0;                            ///< cells along s and t
  std::unique_ptr<std::atomic<uint8_t>[]> cells;  ///< 0 unknown, 1 exposed, 2 buried
};

class ExposureCache;

/// Whether points of one side of one patch are buried (decided per lattice cell, see above).
struct ExposureQuery {
  const ExposureCache* cache = nullptr;
  const ExposureMask* mask = nullptr;
  uint32_t patch = 0;
  int side = 0;
  /// False unless the mask is partial.
  bool buried(const Vec3d& x) const;
};

/// Lazily computed exposure masks of every patch side; thread-safe.
class ExposureCache {
 public:
  /// @p rays traces the same patches as @p mesh; both must outlive the cache. @p grid probe points
  /// per patch edge, @p directions rays per point (a stratified cosine-weighted set).
  ExposureCache(const PatchMesh& mesh, const EmbreeItemBuffer& rays, int grid = 6, int directions = 16)
      : ExposureCache(mesh, rays, rays, grid, directions) {}
  /// The same with the probes traced by @p probeRays (which may be a faster, non-watertight BVH of
  /// the same patches); rays() stays @p rays.
  ExposureCache(const PatchMesh& mesh, const EmbreeItemBuffer& rays, const EmbreeItemBuffer& probeRays, int grid = 6,
                int directions = 16);
  /// The mask of side @p side (0: the normal's side, 1: the other) of patch @p patch.
  const ExposureMask& mask(uint32_t patch, int side);
  /// The ray caster the probes use (the preprocessor's exact point-visibility tests use it too).
  const EmbreeItemBuffer& rays() const { return rays_; }
  /// The ray test itself at point @p x of side @p side of patch @p patch.
  bool probe(uint32_t patch, int side, const Vec3d& x) const;
  /// The nearest probe point's answer at @p x, or the ray test at @p x if that point is on the border.
  bool nearest(uint32_t patch, int side, const ExposureMask& mask, const Vec3d& x) const;
  /// nearest() at the centre of the lattice cell of @p mask holding @p x, decided on first use.
  bool cell(uint32_t patch, int side, const ExposureMask& mask, const Vec3d& x) const;
  /// Lattice cells per grid step.
  static constexpr int kLatticePerStep = 8;

 private:
  void compute(uint32_t patch, int side);

  const PatchMesh& mesh_;
  const EmbreeItemBuffer& rays_;
  const EmbreeItemBuffer& probeRays_;
  int grid_;
  std::vector<Vec3d> directions_;  ///< local frame, z up
  std::unique_ptr<std::once_flag[]> once_;
  std::vector<ExposureMask> masks_;  ///< 2 per patch
  /// Whether a patch not in the plane of @p patch touches it (else no probes): a point query of rays_'s BVH about
  /// its grown box, asked by compute() only (the classroom's 17,000 masks of 133,000 patches).
  bool met(uint32_t patch) const;
  std::vector<GrownBox> boxes_;      ///< per patch: its box grown as patch_neighbours.h has it
  float grow_ = 0.0f;                ///< how much they were grown, m
  double planeTolerance_ = 0;        ///< a vertex this near a patch's plane is in it, m
  double offset_ = 0;                ///< ray origins off the patch, m
};

}  // namespace firstshot
