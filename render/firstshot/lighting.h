#pragma once
/// @file lighting.h
/// The first-shot term of a first-shot table, evaluated at a hit point: what the renderer makes of
/// the factors (docs/firstshot-format.md, "How the renderer uses the factors").
///
/// First-shot term on patch j (see common/table/firstshot.h): Σ_i emission_i · r_ij · f_r(ω'_i, x, ω),
/// with ω'_i the direction from x to light sample i (against the travel direction for
/// directional lights). The BSDF's side test makes a sample on the other side of the patch than
/// the viewer contribute nothing. The sum over a patch's factors is render/firstshot/reflected.h's,
/// which the bundle transfer shares (at the patch centroid, with the patch averages r_ij).
#include <cstdint>
#include <memory>
#include <vector>

#include "common/lights/emission_profile.h"
#include "common/lights/spot_cone.h"
#include "common/materials/bsdf.h"
#include "common/util/math.h"
#include "render/firstshot/near_terms.h"
#include "render/firstshot/reflected.h"
#include "render/firstshot/table_visibility.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"
#include "render/scene/table_rows.h"

namespace firstshot {

/// A spot sample's normalised intensity profile I(ω)/Φ = profile(ω)/∫profile, in 1/sr, for the
/// world direction ω emitted (cone or IES table, common/lights/emission_profile.h).
struct SpotKernel {
  EmissionProfile profile;
  float invIntegral = 0.0f;  ///< 1/∫profile dω, 1/sr
  float operator()(const Vec3& w) const { return profile(w) * invIntegral; }
};

/// The first-shot term of a scene's table, evaluated at the hit point.
///
/// A factor r_ij is patch j's average irradiance from sample i per unit emission. For point lights
/// and area-light vertices it is (scale_i/A_j)·V_ij·U_ij, with U_ij the closed-form integral of the
/// sample's kernel over the whole patch and V_ij the visible fraction (docs/firstshot-format.md);
/// build() recovers V_ij from r_ij. The irradiance at x on patch j is then modelled as
///   E(x) = Σ_i emission_i · V_ij · k_i(x),   k_i(x) = cosθ_x/(4πd²) (point), cosθ_x·profile(θ)/(∫profile·d²)
///   (spot), (S_i/3)·cosθ_x·cosθL/d² (area vertex):
/// the exact unoccluded irradiance at x times the visible fraction, whose average over the patch is
/// the table's Σ_i emission_i r_ij. Evaluated that way for samples closer than kNearPatches patch
/// diameters; the others vary slowly across the patch and are summed, per side of the patch, into
/// their exact patch average plus its gradient at the centroid (a linear term, zero on average):
/// one lookup and one dot product per channel. A spot's U_ij has no closed form: it is integrated
/// numerically over the patch (midpoint rule), so that its E(x) still averages to r_ij.
/// Directional lights (constant over a patch) and degenerate entries contribute their patch average.
class FirstShotLighting {
 public:
  /// Samples closer to a patch's centroid than this many patch diameters are evaluated per point.
  static constexpr float kNearPatches = 4.0f;

  /// Recovers V_ij for every factor, sorts the samples of each patch into near and far, and sums
  /// the far ones per side of each patch's plane; no-op without a table. @p scene must outlive this.
  /// Built once per scene: later builds (and copies) share the scene's kept data (SceneMemo).
  void build(const RenderScene& scene);
  /// The first-shot radiance reflected at a hit on patch hit.patch towards the local @p woLocal
  /// (W/(m² sr) per unit of the BSDF). Requires a table and a hit on a patch.
  Color eval(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const;
  /// First-shot irradiance (W/m²) at the hit point on the side of hit.patch's plane where
  /// @p front says (the side hit.ng points to), from the factors of hit.patch.
  Color irradiance(const Hit& hit, bool front) const;
  /// Whether scene light @p light (a replaced point or spot light) sees all, none or part of patch
  /// @p patch and its neighbours, by the table's visible fractions (render/firstshot/table_visibility.h).
  TableVisibility visibility(uint32_t patch, uint32_t light) const { return d_->visibilityMap_.query(patch, light); }
  /// The same for many lights of one patch, in ascending order.
  TableVisibilityMap::Cursor visibilityCursor(uint32_t patch) const { return d_->visibilityMap_.cursor(patch); }

 private:
  /// Far samples of one side of a patch: E(x) ≈ average + (x − centroid)·gradient per channel.
  struct SideTerm {
    Color average{0.0f};  ///< W/m²
    Vec3 gradient[3] = {Vec3(0.0f), Vec3(0.0f), Vec3(0.0f)};  ///< per channel, in the patch's plane, W/m³
  };
  /// What build() computes from the scene: immutable, shared by the copies of this lighting and the scene's memo.
  struct Data {
    TableRows rows_;  ///< the table's factors by patch
    std::vector<SideTerm> side_;  ///< 2j: samples in front of patch j's plane, 2j+1: behind it
    /// Per factor (TableFactor::index): V_ij, or a negative value for a patch-average entry.
    std::vector<float> visible_;
    std::vector<SpotKernel> spots_;  ///< by light sample: the spot profile (default for other kinds)
    NearTerms near_;  ///< per patch: its near point lights and area vertices, evaluated per point
    /// CSR over patches of their near spots (TableFactor::index): per point through sampleKernel.
    std::vector<uint64_t> nearSpotStart_, nearSpot_;
    TableVisibilityMap visibilityMap_;
  };
  /// The lighting of @p scene as build() computes it.
  static std::shared_ptr<const Data> compute(const RenderScene& scene);

  const RenderScene* scene_ = nullptr;
  std::shared_ptr<const Data> d_ = std::make_shared<const Data>();
};

}  // namespace firstshot
