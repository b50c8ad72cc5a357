#pragma once
/// @file luminaire_boxes.h
/// The first-shot table's luminaires (common/table/luminaire.h) as the renderer meets them: which light belongs to which
/// luminaire, which box holds a point, which boxes a path segment enters, and the exit patches numbered across all
/// luminaires (the light sampler's Exit emitters, render/lights/light_sampler.h).
///
/// How a path uses them without counting a luminaire's light twice (render/integrators/common/path_walk.cpp, after
/// Radiance's illum): from outside a box its exit patches are sampled, and a segment from a non-delta vertex that
/// enters the box adds the exit radiance where it crosses the face (MIS against that NEE). The light that leaves the
/// box straight from its lights is not in the exit distribution: NEE samples the lights for it from outside too, and
/// a segment that enters the box and meets a light before anything else counts it (MIS against that NEE). Nor is the
/// light that leaves it through glass or off mirrors only (Luminaire::intensity): NEE samples it as a point source at
/// the luminaire's centre (the light sampler's Gonio emitter), which no BSDF-sampled path finds.
/// Past the first vertex inside a box entered so, the luminaire's light is counted: its lights then emit
/// nothing, directly or by NEE, until the path leaves the box. A segment from the camera or a delta bounce enters
/// without counting anything, and inside the path sees the luminaire as it is: its lights emit and are sampled.
/// What the exit distribution holds (light that left the box for the first time after a bounce in it), the direct
/// light, and what the path adds by tracing (light that entered it from the room, and the lights' light along
/// segments from delta vertices) are disjoint, and together they are all the light.
#include <cstdint>
#include <vector>

#include "common/table/luminaire.h"
#include "common/util/math.h"

namespace firstshot {

class LightSet;

class LuminaireBoxes {
 public:
  /// A segment enters at most this many boxes (the nearest of them; more would need a row of lamps along one ray).
  static constexpr int kMaxEntries = 64;
  /// A box a segment enters: where and through which face.
  struct Entry {
    uint32_t luminaire = 0;
    int face = 0;
    float t = 0.0f;  ///< ray parameter of the crossing
  };

  LuminaireBoxes() = default;
  /// @p luminaires: the table's (they must outlive this object); @p lights: the scene's lights, whose sceneIndex
  /// maps them onto the luminaires' light lists.
  LuminaireBoxes(const std::vector<Luminaire>* luminaires, const LightSet& lights);

  bool empty() const { return items_ == nullptr || items_->empty(); }
  /// True if some luminaire's light leaves its box straight from its lights (Luminaire::directPower): NEE from
  /// outside the boxes then samples their lights too. False for luminaires behind glass alone.
  bool anyDirect() const { return anyDirect_; }
  /// Whether a vertex samples the luminaires' lights (NeeRequest::inner): inside box @p inside (−1: none) seen as it
  /// is (not @p suppressed), or anywhere for the light that leaves a box straight from its lights.
  bool innerWanted(int inside, bool suppressed) const { return (inside >= 0 && !suppressed) || anyDirect_; }
  const std::vector<Luminaire>& items() const { return *items_; }
  /// The luminaire light @p l (a LightSet index) belongs to, or −1.
  int ofLight(uint32_t l) const { return l < lightLuminaire_.size() ? lightLuminaire_[l] : -1; }
  /// The luminaire whose box holds @p p, or −1.
  int containing(const Vec3& p) const;
  /// The boxes the segment o + t·d, t ∈ (0, tmax), enters from outside, nearest first; returns their number.
  int entries(const Vec3& o, const Vec3& d, float tmax, Entry* out) const;

  /// Exit patches of all luminaires: luminaire i's patch k is number exitFirst(i) + k.
  uint32_t exitCount() const { return exitFirst_.empty() ? 0 : exitFirst_.back(); }
  uint32_t exitFirst(uint32_t luminaire) const { return exitFirst_[luminaire]; }
  /// The luminaire of exit patch number @p e.
  uint32_t exitLuminaire(uint32_t e) const;

  /// Next-event estimation's choice of an exit patch of luminaire @p luminaire (already chosen) for a receiver at
  /// @p x, among the faces whose outer side holds @p x. Mostly (1 − kPowerShare) by what the patches send towards
  /// @p x: a face by its radiance times area in the direction bin of @p x seen from the face's centre, times the
  /// cosine there over the squared distance, then a patch by its radiance times area in that bin; otherwise by power
  /// alone (a face by its power, a patch by its power), so that a patch whose light reaches @p x in another bin than
  /// its face centre's keeps a probability. @p u ∈ [0,1) makes the choice and comes back rescaled within the chosen
  /// patch's share. @return the patch (its number within the luminaire) and in @p p the probability of the choice
  /// (both ways together); false where no face facing @p x emits.
  bool choosePatch(uint32_t luminaire, const Vec3& x, float& u, uint32_t& patch, float& p) const;
  /// The probability with which choosePatch() at @p x chooses patch @p patch of luminaire @p luminaire.
  float patchProbability(uint32_t luminaire, const Vec3& x, uint32_t patch) const;
  /// The share of choosePatch()'s choices made by power alone.
  static constexpr float kPowerShare = 0.2f;

 private:
  /// What choosePatch() weighs the faces of a luminaire by, for one receiver.
  struct FaceWeights {
    bool facing[6];
    float power = 0.0f;            ///< the facing faces' power
    float toward[6];               ///< per face: radiance × area in bin[f] × cos / distance² (0 not facing)
    int bin[6];                    ///< per face: the direction bin of the receiver seen from its centre, or −1
    float towardTotal = 0.0f;
  };
  FaceWeights faceWeights(uint32_t i, const Vec3& x) const;
  float probability(const FaceWeights& w, uint32_t i, uint32_t patch) const;
  /// The CDF over face f's patches of luminaire i by radiance × area in direction bin b, at patch k's entry.
  const float* binCdf(uint32_t i, int b) const {
    return &binCdf_[size_t(Luminaire::kBins) * exitFirst_[i] + size_t(b) * (*items_)[i].patchCount()];
  }

  const std::vector<Luminaire>* items_ = nullptr;
  bool anyDirect_ = false;
  std::vector<int> lightLuminaire_;
  std::vector<uint32_t> exitFirst_;  ///< per luminaire, and the total last
  /// Per exit patch (numbered across luminaires): the CDF of its face's patches by power up to and including it.
  std::vector<float> patchCdf_;
  std::vector<float> facePower_;  ///< per luminaire, 6 per face: the face's power (mean RGB), W
  /// Per luminaire and direction bin, per exit patch: the CDF of its face's patches by radiance × area in that bin
  /// (binCdf()); and per luminaire, face and bin that sum (mean RGB), W/sr.
  std::vector<float> binCdf_, faceBinPower_;
  /// The faces of luminaire @p i whose outer side holds @p x, and their total power.
  float facingPower(uint32_t i, const Vec3& x, bool facing[6]) const;
};

}  // namespace firstshot
