#pragma once
/// @file luminaire_trace.h
/// The particle tracer behind the luminaires (preprocess/luminaires.h): the scene's faces in one Embree BVH, the
/// particles a set of lights emits, and the exit distribution of a luminaire traced from them.
///
/// Physics, as the renderer's light tracing does it (render/integrators/common/subpath_walk.cpp) but on its own
/// code: a particle carries power (W); at a hit the material's BSDF (common/materials/bsdf.h, makeBSDF) is sampled in the frame
/// of the face's geometric normal (its winding: the front side, the outside of glass) in importance mode, so a
/// refraction's weight is the transmittance without the 1/η² of radiance, and the weight multiplies the power.
/// Simplifications, for the walk inside a luminaire's box: shading normals and normal maps are ignored (the
/// geometric normal is the frame, so no adjoint correction arises), alpha cut-outs are ignored (a cut-out surface is
/// solid), a textured albedo is its texture's mean, and an emissive surface absorbs what hits it.
#include <cstdint>
#include <memory>
#include <vector>

#include "common/materials/bsdf.h"
#include "common/sampling/distribution_1d.h"
#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "common/table/luminaire.h"
#include "common/util/math.h"

namespace firstshot {

class Progress;  // common/util/progress.h

/// Every face of every shape of a scene, as triangles in one Embree BVH (the robust flag: no leaks between
/// neighbouring triangles), with each triangle's material and unit geometric normal.
class ParticleScene {
 public:
  explicit ParticleScene(const SceneDesc& scene);
  /// Only the triangles whose bounds meet the box [@p lo, @p hi]: a luminaire's exit trace, whose rays end where they
  /// leave its box, meets the same faces in a BVH of its own box's, the same table 5–17% sooner (veach-bidir's wall
  /// lamp 5.6 → 5.2 s on one thread).
  ParticleScene(const SceneDesc& scene, const Vec3& lo, const Vec3& hi);
  ~ParticleScene();
  ParticleScene(const ParticleScene&) = delete;
  ParticleScene& operator=(const ParticleScene&) = delete;

  /// The first surface a ray meets.
  struct Hit {
    float t = 0.0f;    ///< distance along the unit direction, m
    int material = 0;  ///< index into SceneDesc::materials
    Vec3 ng{0.0f};     ///< unit geometric normal of the face, on its front side (counter-clockwise winding)
    Vec3 lo{0.0f}, hi{0.0f};  ///< the bounds of the hit triangle, m
  };
  /// The first face along the ray from @p o in the unit direction @p d with distance in (@p tnear, @p tfar) (m;
  /// infinity: unbounded); false if there is none.
  bool intersect(const Vec3& o, const Vec3& d, float tfar, Hit& hit, float tnear = 0.0f) const;
  /// How far a new ray starts off a surface at @p p, along its normal, so that it does not meet that surface again, m.
  float offset(const Vec3& p) const;
  /// The scene's bounds (SceneDesc::bounds), m.
  Vec3d lo() const { return lo_; }
  Vec3d hi() const { return hi_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Vec3d lo_{0.0}, hi_{0.0};
};

/// A particle leaving a light.
struct EmittedParticle {
  Vec3 origin{0.0f};     ///< m
  Vec3 direction{0.0f};  ///< unit
  /// Its power estimate, W: the light's emission along the direction over the densities of the choices made (light,
  /// point, direction), so that its mean over many particles is the lights' total power. 0: no particle.
  Color weight{0.0f};
};

/// Particles from a set of lights: a light chosen by its share of the power (mean of RGB), then
/// - point, spot, IES: a direction from the light's emission profile (common/lights/emission_profile.h);
/// - area: a point uniform by area over the emissive shape's faces and a cosine-weighted direction on their front
///   side, the light's power π·Le·A (Le the material's emission: an emission texture's mean radiance).
/// Directional lights emit nothing here (they belong to no luminaire).
class ParticleSource {
 public:
  ParticleSource(const SceneDesc& scene, const std::vector<uint32_t>& lights, const ParticleScene& geometry);
  ~ParticleSource();
  /// The lights' total emitted power, W (per light: Φ of point, spot and IES lights, π·Le·A of area lights).
  Color power() const { return power_; }
  /// The power of light @p l of the scene (0 for a directional light), W.
  static Color lightPower(const SceneDesc& scene, uint32_t l);
  /// One particle, from three dimensions of @p sampler (one 1D, one 2D) and two more for an area light.
  EmittedParticle sample(Sampler& sampler) const;

 private:
  struct Emitter;
  std::vector<Emitter> emitters_;
  Distribution1D byPower_;  ///< the emitters by mean power
  Color power_{0.0f};
  const ParticleScene& geometry_;
};

/// One walk's way out of a luminaire's box.
struct ParticleExit {
  /// Direct: straight from its light, met by nothing inside the box (Luminaire::directPower); Specular: after delta
  /// bounces only (Luminaire::specularPower, intensity); Scattered: after a bounce off a non-delta surface (the exit
  /// distribution).
  enum class Kind : uint8_t { Scattered, Direct, Specular } kind = Kind::Scattered;
  uint32_t cell = 0;     ///< kBins·(exit patch) + (direction bin)
  Color power{0.0f};     ///< W (a particle's power estimate, as EmittedParticle::weight)
  Vec3 point{0.0f};      ///< where it leaves the box, m
  Vec3 direction{0.0f};  ///< unit, the way it leaves
};

/// The walk's limits: Russian roulette from this many bounces on (survival min(0.95, largest component of the
/// throughput), the survivor divided by it), and no particle past this many bounces.
inline constexpr int kLuminaireRouletteDepth = 3;
inline constexpr int kLuminaireMaxBounces = 64;

/// Walks the particle @p p through the surfaces inside @p box (its lo, hi, nu, nv) until it leaves the box (true,
/// @p out filled) or is absorbed, killed by Russian roulette or past kLuminaireMaxBounces (false). @p bsdfs: one per
/// material of @p scene (makeLuminaireBSDFs).
bool walkParticle(const SceneDesc& scene, const ParticleScene& geometry, const std::vector<BSDF>& bsdfs,
                  const Luminaire& box, EmittedParticle p, Sampler& sampler, ParticleExit& out);

/// The BSDF of each material of @p scene for the walk: makeBSDF with a textured albedo replaced by its mean.
std::vector<BSDF> makeLuminaireBSDFs(const SceneDesc& scene);

/// Traces @p particles particles (particle i's numbers from Sampler::sobol(seed, index, i), kLuminaireChunk per chunk) from
/// the lights of @p lum through its box, and fills its radiance, power, exitPower, directPower, specularPower, centre,
/// intensity, particles, relError and the table's own errors (cellError, farError, intensityError): the radiance and
/// exitPower hold the particles that met a non-delta surface inside the box, directPower those that met nothing (the
/// renderer samples the lights themselves for that light), specularPower and intensity those that met delta surfaces
/// only (glass, mirrors), about the centre. The
/// chunks run in parallel (TBB) and are summed in double in chunk order: the result does not depend on the number of
/// threads. @p progress, when not null, advances by one per chunk.
void traceExitDistribution(const SceneDesc& scene, const ParticleScene& geometry, Luminaire& lum, uint32_t index,
                           uint64_t particles, uint64_t seed, Progress* progress = nullptr);

/// Particles per chunk of traceExitDistribution (each chunk its own random numbers).
inline constexpr uint64_t kLuminaireChunk = 4096;

}  // namespace firstshot
