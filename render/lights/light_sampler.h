#pragma once
/// @file light_sampler.h
/// Light sampling: which emitter next-event estimation (render/lights/next_event.h) takes at a shading
/// point, and with what probability (as pbrt-v4's LightSampler). It chooses only; the point on the
/// emitter, the shadow ray, the BSDF and the MIS weight are next_event.cpp's.
///
/// The emitters: the lights the renderer keeps, the small lights a first-shot table replaces (for
/// vertices that still sample them), and the lit first-shot patch sides. A lit patch j emits on
/// side s (s = 0: the side its normal faces) the first-shot radiance Σ_i e_i r_ij f_r(ω'_i, y, ω)
/// of FirstShotLighting: a smooth, spatially extended source of power ≈ albedo · E_js · A_j.
/// Sampling it directly is what turns the table's smoothness into lower variance: a path no longer
/// has to hit the lit patches by chance.
///
/// They fall into three groups (LightGroup: kept lights, replaced lights, patches); a vertex asks
/// for one emitter of each group it takes. Strategies (LightStrategy):
/// - Tree: in each light group, one light chosen by a light tree (light_tree.h); area lights enter
///   the trees triangle by triangle. Directional lights are chosen uniformly beside a tree with
///   probability n_dir/(n_dir + 1). The scene's infinite light (a sky or an environment map,
///   LightSet::environment) counts as one more of them in the kept group, as pbrt-v4's
///   BVHLightSampler gives its infinite lights a fixed share: (n_dir + 1)/(n_dir + 2) for all of them.
/// - All: no light is chosen: NEE takes every light with probability 1 (nextEventEveryLight).
/// Either way the patches group is a tree over the patch emitters. The trees' top levels are
/// weighted by the visibility of their emitters from each grid cell (light_sampler_visibility.cpp).
/// A sampler may be built over a subset of the lights (build()'s @c include mask; the irradiance
/// cache samples only its direct lights): the others are never chosen and have pmf() 0.
#include <cstdint>
#include <vector>

#include "render/firstshot/lighting.h"
#include "render/lights/light_tree.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

enum class LightStrategy : uint8_t { All, Tree };

/// The groups a LightSampler chooses one emitter in (NeeRequest::kept, replaced, patches, inner). With luminaires
/// (build()'s @c luminaires, render/scene/luminaire_boxes.h) their exit patches and specular light are kept emitters
/// and their lights the Inner group, for vertices inside a luminaire that see it as it is.
enum class LightGroup : uint8_t { Kept = 0, Replaced = 1, Patches = 2, Inner = 3 };

/// Something a LightSampler chooses.
struct Emitter {
  /// Environment: the scene's infinite light (LightSet::environment), a direction, no point.
  /// Exit: a luminaire, whose exit patch next-event estimation then chooses (LuminaireBoxes::choosePatch).
  /// Gonio: a luminaire's specular light (Luminaire::intensity), a point source at its centre whose shadow ray stops
  /// where it enters the box.
  enum class Kind : uint8_t { Light, Triangle, Patch, Environment, Exit, Gonio } kind = Kind::Light;
  uint32_t index = 0;  ///< LightSet index (Light, Triangle), patch ID or luminaire (Exit, Gonio)
  uint32_t sub = 0;    ///< Triangle: LightSampler::triangle() index; Patch: the side (0 front, 1 back); Exit: its luminaire
  float area = 0.0f;   ///< m² (Triangle, Patch)
};

/// An emitter chosen for a shading point and the probability of that choice (pbrt-v4's SampledLight).
struct SampledEmitter {
  Emitter emitter;
  float p = 0.0f;  ///< probability of the choice, > 0
};

/// An area light's triangle as NEE samples it: vertex a, edges b − a and c − a, unit normal.
struct TriangleEmitter {
  Vec3 a, e1, e2, n;
  uint32_t meshTriangle = 0;  ///< its index in the light's emitter mesh (RenderLight::triangleUv)
};

class LightSampler {
 public:
  LightSampler() = default;
  /// Builds the emitters and trees. @p patchEmitters: make the lit patches emitters (needs a
  /// table and @p firstShot built for the same scene). Both must outlive this object.
  /// @p visibility: weight the trees' top levels by the visibility of their emitters from each
  /// grid cell (light_tree.h, VisibilityGrid), estimated here with a few shadow rays per cell.
  /// @p include: if set, only the lights l with (*include)[l] != 0 (LightSet indices) are
  /// sampled; the mask is copied. The infinite light (sky, environment map) is sampled without @p include, or with
  /// it when @p infinite.
  /// @p luminaires: the table's luminaires replace their lights for vertices outside them (their exit patches join
  /// the kept group, their lights form the Inner group); only under LightStrategy::Tree.
  /// The same arguments on the same scene are built once: later builds copy the scene's kept sampler (SceneMemo).
  void build(const RenderScene& scene, const FirstShotLighting& firstShot, LightStrategy strategy, bool patchEmitters,
             bool visibility = true, const std::vector<uint8_t>* include = nullptr, bool infinite = false,
             bool luminaires = false);

  LightStrategy strategy() const { return strategy_; }
  const RenderScene& scene() const { return *scene_; }
  /// The first-shot radiance of the patch emitters, and the table's visibility of the small lights.
  const FirstShotLighting& lighting() const { return *firstShot_; }
  /// Per LightSet light: 1 if this sampler may choose it (build()'s @c include).
  const std::vector<uint8_t>& included() const { return included_; }
  /// True if the scene's luminaires are sampled by their exit patches (build()'s @c luminaires, and some exist).
  bool hasLuminaires() const { return luminaires_; }
  /// True if patch emitters exist (a table with lit patches and patch emitters asked for).
  bool hasPatchEmitters() const { return patchCount_ > 0; }
  /// True if the patches group was built (patch emitters asked for, with a table), lit patches or not.
  bool hasPatchGroup() const { return patchGroup_ != kNone; }
  /// Group @p g has nothing to choose (always so for the light groups under LightStrategy::All).
  bool empty(LightGroup g) const { return groups_[size_t(g)].empty(); }

  /// Chooses one emitter of group @p g for the receiver at @p x with receiving side normal @p n
  /// from @p u ∈ [0,1). @return false if the group has none that can light @p x. @p rest, if
  /// given, gets u rescaled within the chosen emitter's share of [0,1) (LightTree::sample).
  bool sample(LightGroup g, const Vec3& x, const Vec3& n, float u, SampledEmitter& out, float* rest = nullptr) const;
  /// The probability with which sample() at @p x, @p n chooses the emitter that the hit @p y lies
  /// on (an area-light triangle, or the side of a patch that faces @p x), that emitter's area in
  /// @p area (m²); 1 for an included light under LightStrategy::All. 0 where @p y is on no emitter
  /// of this sampler. Whether the emitter's group was asked for is the caller's matter.
  float pmf(const Vec3& x, const Vec3& n, const Hit& y, float& area) const;
  /// The probability with which sample() chooses the infinite light (the same at every point): 1 under
  /// LightStrategy::All, 0 without one or when build()'s @c include leaves lights out.
  float environmentPmf() const;
  /// The probability with which sample() at @p x, @p n chooses exit patch number @p exit (LuminaireBoxes), its area
  /// in @p area (m²); 0 without luminaires or for a patch that emits nothing.
  float exitPmf(const Vec3& x, const Vec3& n, uint32_t exit, float& area) const;

  /// A point of emitter @p e for @p u ∈ [0,1)² (uniform by area; the position of a point light).
  Vec3 emitterPoint(const Emitter& e, const Vec2& u) const;
  /// The radiance leaving the point emitterPoint(@p e, @p u) of Triangle emitter @p e (LightSet::radianceAt).
  Color emitterRadiance(const Emitter& e, const Vec2& u) const;
  /// The triangle of a Triangle emitter.
  const TriangleEmitter& triangle(const Emitter& e) const { return triangles_[e.sub]; }

 private:
  /// A tree and the emitters it chooses from, with the directional lights beside it.
  struct Group {
    LightTree tree;
    std::vector<Emitter> emitters;
    std::vector<uint32_t> directional;  ///< LightSet indices
    bool environment = false;           ///< the infinite light is chosen beside the tree, after the directional lights
    /// Directional lights and the infinite light: chosen uniformly beside the tree.
    uint32_t besideCount() const { return uint32_t(directional.size()) + (environment ? 1u : 0u); }
    float pDirectional() const;
    /// Nothing to sample (no directional or infinite light, no tree).
    bool empty() const { return besideCount() == 0 && tree.empty(); }
  };
  enum GroupId : uint8_t { kKept = 0, kReplaced = 1, kPatches = 2, kInner = 3, kNone = 255 };
  static constexpr int kGroups = 4;

  void addLight(Group& g, GroupId id, uint32_t l, std::vector<LightBounds>& bounds);
  void addPatches(Group& g, GroupId id, std::vector<LightBounds>& bounds);
  void addExits(Group& g, std::vector<LightBounds>& bounds);
  float selectProbability(const Group& g, const Vec3& x, const Vec3& n, uint32_t emitter) const;
  /// The emitter index of a hit on a patch seen from @p x in its group's tree, or kNoId.
  uint32_t patchEmitter(const Hit& y, const Vec3& x) const;
  /// build() without the scene's memo; @p luminaires as build() reduced it (only with the tree, where the scene has some).
  void buildAnew(const RenderScene& scene, const FirstShotLighting& firstShot, LightStrategy strategy,
                 bool patchEmitters, bool visibility, const std::vector<uint8_t>* include, bool infinite,
                 bool luminaires);
  /// Builds the visibility grid and sets every tree's visibility factors (light_sampler_visibility.cpp).
  void buildVisibility();

  const RenderScene* scene_ = nullptr;
  const FirstShotLighting* firstShot_ = nullptr;
  LightStrategy strategy_ = LightStrategy::Tree;
  Group groups_[kGroups];
  std::vector<TriangleEmitter> triangles_;  ///< the Triangle emitters of all groups
  size_t patchCount_ = 0;
  // Where each emitter lives: per LightSet light its group and first emitter (its triangles
  // follow in order); per patch side (2j + s) its emitter in the patch group.
  std::vector<uint8_t> included_;  ///< per LightSet light: sampled by this sampler
  std::vector<uint8_t> lightGroup_;
  std::vector<uint32_t> lightFirst_;
  uint8_t patchGroup_ = kNone;
  std::vector<uint32_t> patchSide_;
  bool luminaires_ = false;
  std::vector<uint32_t> exitEmitter_;  ///< per luminaire: its emitter in the kept group, or kNoId
};

}  // namespace firstshot
