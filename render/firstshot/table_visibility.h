#pragma once
/// @file table_visibility.h
/// Visibility of the small point and spot lights from the patches, as a first-shot table knows it:
/// where it is certain, the camera-visible surfaces need no shadow ray (--table-visibility).
///
/// The table's visible fraction V_ij comes from pixel centres of light sample i's item buffers, so
/// a shadow edge that crosses patch j between its pixel centres leaves V_ij at 1 (or the factor
/// absent) though part of the patch is in shadow. Such an edge also crosses a neighbour of j whose
/// class differs, so a patch is certain only together with every patch it touches:
/// - Visible: V = 1 (within kVisibleTolerance) on the patch and on all its neighbours;
/// - Hidden: no factor on the patch or on any neighbour (nothing of the light reaches them);
/// - Unknown otherwise: a shadow ray decides.
/// What stays uncertain: shadows that fit between pixel centres of every patch they touch (an
/// occluder thinner than the item buffers' pixel spacing seen from the light).
/// Neighbours are the patches whose bounding boxes, grown by 10⁻⁵ of the scene's diagonal, overlap
/// (common/patches/patch_neighbours.h: T-junctions of adaptive meshes included; patches of another surface
/// that touch count too, which only leaves more to rays).
#include <cstdint>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"

namespace firstshot {

/// What the table says about a small light's visibility from a patch.
enum class TableVisibility : uint8_t {
  Unknown,  ///< partly visible, next to a patch that differs, not a point or spot light: trace a ray
  Visible,  ///< the patch and its neighbours see the whole light (V = 1)
  Hidden,   ///< neither the patch nor a neighbour receives anything from the light
};

class TableVisibilityMap {
 public:
  /// |V_ij − 1| up to which a patch counts as seeing light sample i whole (float rounding of r_ij).
  static constexpr float kVisibleTolerance = 1e-4f;

  /// Builds the map of @p table, whose visible fractions per factor are @p visible (V_ij, negative
  /// where unknown), for a scene of lights @p lights: only a point or spot light's sample says where
  /// its light is seen (an area light's point samples, a sphere's, stand inside it).
  void build(const FirstShotTable& table, const std::vector<float>& visible, const std::vector<LightDesc>& lights);
  /// The class of scene light @p light (index into SceneDesc::lights) at patch @p patch; Unknown
  /// for a light the table does not replace by one point or spot sample, or before build().
  TableVisibility query(uint32_t patch, uint32_t light) const;

  /// query() for one patch and many lights: cheapest when the lights come in ascending order.
  class Cursor {
   public:
    Cursor() = default;
    TableVisibility next(uint32_t light);

   private:
    friend class TableVisibilityMap;
    const TableVisibilityMap* map_ = nullptr;
    const uint32_t *begin_ = nullptr, *end_ = nullptr, *at_ = nullptr;
  };
  /// A cursor over patch @p patch's entries (every query Unknown before build()).
  Cursor cursor(uint32_t patch) const;

 private:
  static constexpr uint32_t kWhole = 0x80000000u;  ///< flag in entries_: Visible
  std::vector<uint32_t> sampleOfLight_;  ///< per scene light: its point or spot sample, or kNoId
  /// CSR over patches: the samples that reach the patch or a neighbour, ascending, kWhole set where
  /// all of them see the sample whole.
  std::vector<uint64_t> start_;
  std::vector<uint32_t> entries_;
};

}  // namespace firstshot
