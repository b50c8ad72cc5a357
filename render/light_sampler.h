#pragma once
/// @file light_sampler.h
/// Next-event estimation over everything that emits: the lights the renderer keeps, the small
/// lights a first-shot table replaces (for vertices that still sample them), and the first-shot
/// patches as area emitters.
///
/// A lit patch j emits on side s (s = 0: the side its normal faces) the first-shot radiance
/// Σ_i e_i r_ij f_r(ω'_i, y, ω) of FirstShotLighting: a smooth, spatially extended source of power
/// ≈ albedo · E_js · A_j. Sampling it directly is what turns the table's smoothness into lower
/// variance: a path no longer has to hit the lit patches by chance.
///
/// Strategies (LightStrategy):
/// - All: one sample of every requested light (NEE to every light).
/// - Tree: one light chosen by a light tree (light_tree.h) over the kept lights, and one from a
///   tree over the replaced lights when those are requested; area lights enter the trees triangle
///   by triangle. Directional lights are chosen uniformly beside a tree with probability
///   n_dir/(n_dir + 1).
/// Either way, when the patches are requested, one patch chosen by a tree over the patch emitters.
/// Area emitters (area-light triangles, patches) are weighted against BSDF sampling by the power
/// heuristic: a path that meets one must weight it with pdf() of the vertex it came from
/// (unless NeeRequest::mis is false: then weight 1, and BSDF sampling must not count them).
/// A sampler may be built over a subset of the lights (build()'s @c include mask; the irradiance
/// cache samples only its direct lights): the others are never chosen and have pdf() 0.
#include <cstdint>
#include <vector>

#include "common/bsdf.h"
#include "common/rng.h"
#include "render/firstshot/lighting.h"
#include "render/light_tree.h"
#include "render/ray.h"
#include "render/render_scene.h"

namespace fs {

enum class LightStrategy : uint8_t { All, Tree };

/// What one vertex takes by next-event estimation.
struct NeeRequest {
  bool kept = false;      ///< the lights the table does not replace (every light without a table)
  bool replaced = false;  ///< the table's small lights (a vertex that does not use the table)
  bool patches = false;   ///< the first-shot patches
  /// Weight area emitters against BSDF sampling (power heuristic); false: weight 1, for callers
  /// whose BSDF-sampled rays never count these emitters.
  bool mis = true;
  /// Replaced point and spot lights at a hit on a patch: no shadow ray where the table finds the
  /// light visible from the whole patch or from none of it (FirstShotLighting::visibility).
  bool tableVisibility = false;
};

/// One point of a lit first-shot patch chosen for a receiver (LightSampler::samplePatch).
struct PatchSample {
  Vec3 wi{0.0f};        ///< unit direction from the receiver to the point
  float distance = 0;   ///< m
  Color Le{0.0f};       ///< first-shot radiance the point sends towards the receiver, W/(m² sr)
  float pdf = 0;        ///< solid-angle density of wi (emitter choice included), sr⁻¹
};

class LightSampler {
 public:
  LightSampler() = default;
  /// Builds the emitters and trees. @p patchEmitters: make the lit patches emitters (needs a
  /// table and @p firstShot built for the same scene). Both must outlive this object.
  /// @p visibility: weight the trees' top levels by the visibility of their emitters from each
  /// grid cell (light_tree.h, VisibilityGrid), estimated here with a few shadow rays per cell.
  /// @p include: if set, only the lights l with (*include)[l] != 0 (LightSet indices) are
  /// sampled; the mask is copied.
  void build(const RenderScene& scene, const FirstShotLighting& firstShot, LightStrategy strategy, bool patchEmitters,
             bool visibility = true, const std::vector<uint8_t>* include = nullptr);

  LightStrategy strategy() const { return strategy_; }
  /// True if patch emitters exist (a table with lit patches and patch emitters asked for).
  bool hasPatchEmitters() const { return patchCount_ > 0; }

  /// NEE at a non-delta vertex: Σ f·|cos θ_i|·L/pdf over the chosen emitters that are unoccluded,
  /// area emitters weighted against BSDF sampling. @p rays counts the shadow rays.
  Color sample(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf, const NeeRequest& request,
               Sampler& sampler, uint64_t& rays) const;

  /// Solid-angle density with which sample() at @p x, receiving side normal @p n, under
  /// @p request, picks the point of @p y: a hit on an area light or on a patch. 0 where that
  /// emitter is not requested (or not an emitter).
  float pdf(const Vec3& x, const Vec3& n, const NeeRequest& request, const Hit& y) const;

  /// Chooses a point of a lit patch for the receiver at @p x with receiving side normal @p n from
  /// @p u ∈ [0,1)³ (u.x the patch, u.yz the point), as sample() does for NeeRequest::patches,
  /// without a shadow ray. @return false if none was chosen or it sends nothing towards @p x;
  /// otherwise @p s.pdf equals pdf(x, n, {patches}, hit at the point).
  bool samplePatch(const Vec3& x, const Vec3& n, const Vec3& u, PatchSample& s) const;

  /// The emitter index of a hit on a patch seen from @p x in its group's tree, or kNoId.
  uint32_t patchEmitter(const Hit& y, const Vec3& x) const;

 private:
  struct Emitter {
    enum class Kind : uint8_t { Light, Triangle, Patch } kind = Kind::Light;
    uint32_t index = 0;  ///< LightSet index (Light, Triangle) or patch ID
    uint32_t sub = 0;    ///< Triangle: index in triangles_; Patch: the side (0 front, 1 back)
    float area = 0.0f;   ///< m² (Triangle, Patch)
  };
  /// An area light's triangle as NEE samples it: vertex a, edges b − a and c − a, unit normal.
  struct TriangleEmitter {
    Vec3 a, e1, e2, n;
  };
  /// A tree and the emitters it chooses from, with the directional lights beside it.
  struct Group {
    LightTree tree;
    std::vector<Emitter> emitters;
    std::vector<uint32_t> directional;  ///< LightSet indices
    float pDirectional() const;
    /// Nothing to sample (no directional light, no tree).
    bool empty() const { return directional.empty() && tree.empty(); }
  };
  enum GroupId : uint8_t { kKept = 0, kReplaced = 1, kPatches = 2, kNone = 255 };

  void addLight(Group& g, GroupId id, uint32_t l, std::vector<LightBounds>& bounds);
  void addPatches(Group& g, GroupId id, std::vector<LightBounds>& bounds);
  /// One emitter of group @p g, chosen from u[0], its point from u[1..2]: its weighted contribution.
  Color sampleGroup(const Group& g, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                    const Vec3& n, const Vec3& u, const NeeRequest& request, uint64_t& rays) const;
  Color contribution(const Emitter& e, float pSelect, const Hit& hit, const Frame& frame, const Vec3& woLocal,
                     const BSDF& bsdf, const Vec2& u, const NeeRequest& request, uint64_t& rays) const;
  /// The point of patch emitter @p e for @p u, seen from @p x: rec.value = Le/pdf. False if it
  /// sends nothing towards @p x.
  bool patchPoint(const Emitter& e, float pSelect, const Vec3& x, const Vec2& u, LightRecord& rec, Color& Le) const;
  float selectProbability(const Group& g, const Vec3& x, const Vec3& n, uint32_t emitter) const;
  /// A point of emitter @p e for @p u ∈ [0,1)² (uniform by area; the position of a point light).
  Vec3 emitterPoint(const Emitter& e, const Vec2& u) const;
  /// Builds grid_ and sets every tree's visibility factors (light_sampler_visibility.cpp).
  void buildVisibility();

  const RenderScene* scene_ = nullptr;
  const FirstShotLighting* firstShot_ = nullptr;
  LightStrategy strategy_ = LightStrategy::Tree;
  Group groups_[3];
  std::vector<TriangleEmitter> triangles_;  ///< the Triangle emitters of all groups
  size_t patchCount_ = 0;
  // Where each emitter lives: per LightSet light its group and first emitter (its triangles
  // follow in order); per patch side (2j + s) its emitter in the patch group.
  std::vector<uint8_t> included_;  ///< per LightSet light: sampled by this sampler
  std::vector<uint8_t> lightGroup_;
  std::vector<uint32_t> lightFirst_;
  uint8_t patchGroup_ = kNone;
  VisibilityGrid grid_;
  std::vector<uint32_t> patchSide_;
};

}  // namespace fs
