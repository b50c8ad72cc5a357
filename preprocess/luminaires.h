#pragma once
/// @file luminaires.h
/// The preprocessor's luminaires (common/table/luminaire.h): which small lights form one, with which box, and the exit
/// distribution traced from their particles (preprocess/luminaire_trace.h).
///
/// Finding them (findLuminaires):
/// 1. Named: the shapes and lights of one "luminaire" name (docs/scene-format.md, *Luminaires*) form one; its box
///    bounds them, its lights are its small lights (a large light named in one stays large; directional lights are
///    never in one).
/// 2. Detected (LuminaireOptions::mode "auto"), among the other small lights but directional ones: kProbeParticles
///    particles from the light (Sampler(seed, kProbeStream, light)), each particle's first hit. The light is a
///    luminaire when (a) at least kGlassShare of its power first hits glass (a dielectric material, smooth or rough):
///    the box bounds the faces hit there (whole triangles, so that a glass envelope lies inside it) and the light; or
///    else (b) at least kNearShare of its power first hits surfaces within a radius R of the light's centre: the box
///    bounds those hit points and the light. R is kFixtureScale × the 90th percentile of the length of the probes'
///    next segment after a diffuse bounce at their first hit (the room's scale as the light sees it: the light a bowl
///    or shade lets out crosses the room, however much of it meets the fixture again; a downlight's floor light goes
///    as far as it came, so the floor is not near), and at most kNearRadius × the scene's bounding-box diagonal.
/// Every box then grows by 1e-3 of its own diagonal plus 1e-5 of the scene's (a light or surface on its boundary is
/// inside it). A detected box then takes in whole every shape it cuts that reaches at most kWholeShapeReach × its
/// extent past it (holdWholeShapes: the parts of a lamp its light does not reach first, a tube's end, an arm), and
/// luminaires whose boxes overlap (or touch) are merged until none do, as long as the merged box's
/// diagonal stays within kNearRadius × the scene's; where it would not, the detected ones among the two are dropped
/// (their lights stay ordinary small lights: a row of desk lamps is not one room-sized luminaire).
/// Exit patches: a face of the box is cut into cells of about s = longest box edge / 8, between 1 and 8 along
/// each edge.
#include <cstdint>
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/table/luminaire.h"

namespace firstshot {

class ParticleScene;

/// How firstshot-preprocess finds and traces luminaires (--luminaires, --luminaire-particles).
struct LuminaireOptions {
  std::string mode = "auto";      ///< auto: named and detected | named: only named | off: none
  /// Particles traced for all luminaires together, shared by their lights' power, at least kMinLuminaireParticles
  /// each (a multiple of 4096 keeps every chunk full).
  uint64_t particles = 4194304;
  uint64_t seed = 1;              ///< the random numbers' seed (probes and walks)
  bool quiet = true;              ///< no progress or warnings on stderr
};

/// Detection's thresholds (see the file comment).
inline constexpr int kProbeParticles = 4096;
inline constexpr uint64_t kMinLuminaireParticles = 65536;
inline constexpr double kGlassShare = 0.9;
inline constexpr double kNearShare = 0.5;
inline constexpr double kNearRadius = 0.1;
inline constexpr double kFixtureScale = 0.25;
inline constexpr double kWholeShapeReach = 0.25;
inline constexpr uint64_t kProbeStream = 0x70726f6265ull;  ///< the probes' "pixel" key: apart from the walks'

/// The luminaires of @p scene among @p smallLights (indices into scene.lights, ascending: the small-light rule,
/// common/lights/small_light_rule.h): boxes, lights, exit patches and names, without exit distributions. Named ones first, in
/// the order their names first appear (shapes, then lights), then detected ones by light index. @p geometry: the
/// scene's particle BVH, built here when null and needed.
std::vector<Luminaire> findLuminaires(const SceneDesc& scene, const std::vector<uint32_t>& smallLights,
                                      const LuminaireOptions& options, const ParticleScene* geometry = nullptr);

/// Grows @p lum's box until it cuts no shape of @p scene that reaches at most kWholeShapeReach × the box's extent
/// (as given, per axis) past its faces: such a shape with a face inside the box and bounds outside it is taken in
/// whole (its bounds, plus the margin of 1e-3 of the new box's diagonal and 1e-5 of @p sceneDiagonal). An exit face
/// that cuts through a lamp spreads the light crossing it inside the lamp over the whole patch, also where the lamp's
/// part outside the box would have blocked it: the walls beside the lamp too bright (docs/luminaires.md). Shapes
/// reaching farther (the wall or ceiling a lamp hangs on, its stand, the desk it
/// stands on) stay cut. Returns the shapes taken in, in the order taken.
std::vector<uint32_t> holdWholeShapes(const SceneDesc& scene, Luminaire& lum, double sceneDiagonal);

/// Exit patches of the box [@p lo, @p hi]: s = longest edge / 8, per face nu = clamp(round(extent_u / s), 1, 8),
/// nv likewise.
void setExitPatches(Luminaire& lum);

/// findLuminaires, then each one's exit distribution traced (traceExitDistribution, its share of options.particles),
/// with progress on stderr unless options.quiet. @p seconds, when not null, receives each luminaire's tracing time.
std::vector<Luminaire> makeLuminaires(const SceneDesc& scene, const std::vector<uint32_t>& smallLights,
                                      const LuminaireOptions& options, std::vector<double>* seconds = nullptr);

/// One line about a traced luminaire: its name, lights, box size, exit patches, particles, exit power over emitted
/// power, relative error and @p seconds.
std::string luminaireSummary(const Luminaire& lum, double seconds);

}  // namespace firstshot
