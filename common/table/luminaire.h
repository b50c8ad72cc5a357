#pragma once
/// @file luminaire.h
/// A luminaire: one or more small lights and what surrounds them (a bowl, a shade, a glass envelope), inside an
/// axis-aligned box whose six faces are its exit surfaces (Radiance's mkillum, one step further than first-shot).
///
/// The preprocessor traces the lights' particles inside the box, through every surface there, until they leave it,
/// and tabulates the radiance leaving each exit patch per outgoing direction: the exit distribution. Three parts of
/// the light are not in it: what leaves the box straight from a light, met by nothing inside (the direct light,
/// directPower: the renderer samples the lights themselves for it, exactly, as for any light); what leaves it after
/// delta bounces only, through glass or off mirrors (the specular light, specularPower: a point-like source's field,
/// which patch × direction bins cannot hold, kept as a goniophotometric distribution, an intensity per direction about
/// its photometric centre, as an IES file holds a luminaire's far field); and light that leaves the box again after
/// entering it from the room (the renderer finds that by tracing).
///
/// Exit patches: face f = 2·axis + (1 on the box's high side, 0 on its low side), outward normal ±e_axis; its
/// tangent axes are u = (axis + 1) mod 3 and v = (axis + 2) mod 3, cut into nu[f] × nv[f] equal rectangles,
/// patch (i, j) of face f numbered firstPatch(f) + i + nu[f]·j. Directions: kThetaBins bins uniform in sin²θ (θ from
/// the outward normal) × kPhiBins uniform in φ = atan2(ω_v, ω_u): every bin covers π/kBins of projected solid
/// angle, so a particle of power Φ leaving patch k in bin b adds Φ·kBins/(π·A_k) to its radiance.
///
/// The specular light's intensity: kGonioThetaBins bins uniform in cos θ (θ from +y) × kGonioPhiBins uniform in
/// φ = atan2(ω_z, ω_x), each 4π/kGonioBins sr, so a particle of power Φ in bin b adds Φ·kGonioBins/(4π) to its
/// intensity; looked up bilinearly between bin centres (intensityAt), which keeps the integral.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/util/math.h"

namespace firstshot {

/// One exit patch: a rectangle on a face of a luminaire's box.
struct ExitPatch {
  Vec3 corner{0.0f};  ///< its corner of least u and v, m
  Vec3 eu{0.0f};      ///< edge along u, m
  Vec3 ev{0.0f};      ///< edge along v, m
  Vec3 normal{0.0f};  ///< outward unit normal
  float area = 0.0f;  ///< m²
  int face = 0;
  /// The point at (s, t) ∈ [0,1)² of the rectangle.
  Vec3 point(const Vec2& st) const { return corner + st.x * eu + st.y * ev; }
};

struct Luminaire {
  static constexpr int kThetaBins = 8;
  static constexpr int kPhiBins = 16;
  static constexpr int kBins = kThetaBins * kPhiBins;
  static constexpr int kGonioThetaBins = 16;
  static constexpr int kGonioPhiBins = 32;
  static constexpr int kGonioBins = kGonioThetaBins * kGonioPhiBins;

  std::string name;            ///< the scene's name for it, or "auto:<first light's name>" when detected
  Vec3 lo{0.0f}, hi{0.0f};     ///< the box, m (world space)
  std::vector<uint32_t> lights;       ///< its lights, indices into SceneDesc::lights, ascending
  std::array<uint32_t, 6> nu{{1, 1, 1, 1, 1, 1}};  ///< exit patches along each face's u axis
  std::array<uint32_t, 6> nv{{1, 1, 1, 1, 1, 1}};  ///< exit patches along each face's v axis
  /// Per exit patch, per direction bin, RGB: the radiance leaving the patch, W/(m² sr);
  /// radiance[3·(kBins·k + b) + c]. Size 3·kBins·patchCount().
  std::vector<float> radiance;
  uint64_t particles = 0;      ///< particles traced for it
  Color power{0.0f};           ///< emitted by its lights, W
  Color exitPower{0.0f};       ///< leaving the box after a bounce inside it (the exit distribution's integral), W
  Color directPower{0.0f};     ///< leaving the box straight from its lights (not in the exit distribution), W
  /// Leaving the box after delta bounces only (glass, mirrors; not in the exit distribution), W: the integral of
  /// intensity.
  Color specularPower{0.0f};
  /// The specular light's photometric centre, m (in the box): the point nearest, by least squares weighted by power,
  /// to the lines its particles leave along (the light's position for a bulb centred in a glass ball).
  Vec3 centre{0.0f};
  /// Per direction bin, RGB: the specular light's intensity about the centre, W/sr; intensity[3·b + c], size
  /// 3·kGonioBins.
  std::vector<float> intensity;
  /// Relative standard error of the exit power's luminance, from the particles (the table's own noise per patch and
  /// bin is larger: see docs/luminaires.md).
  float relError = 0.0f;
  /// The table's own error, each a power-weighted mean of relative standard errors Σ σ_i / Σ S_i over bins i of the
  /// luminance S_i, σ_i from the particles taken as independent (where the Sobol' numbers stratify a bin, as the
  /// specular light's, the true error is smaller; the exit radiance's far field shows it as stated: tests/
  /// test_luminaire_preprocess.cpp): per exit patch and direction bin (cellError: what a point beside the box sees),
  /// per face and direction bin (farError: a face's far field, what a point a few box sizes away sees), and per
  /// direction bin of the specular intensity (intensityError). 0 where nothing left that way.
  float cellError = 0.0f, farError = 0.0f, intensityError = 0.0f;

  uint32_t patchCount() const;
  /// The number of the first exit patch of face @p f (f = 6: patchCount()).
  uint32_t firstPatch(int f) const;
  /// Exit patch @p k's rectangle.
  ExitPatch patch(uint32_t k) const;
  /// The exit patch of face @p f holding point @p p (on that face; clamped to it).
  uint32_t patchAt(int f, const Vec3& p) const;
  /// The direction bin of the unit direction @p w leaving face @p f, or −1 when it points into the box.
  static int bin(int f, const Vec3& w);
  /// The radiance leaving exit patch @p k along the unit direction @p w (0 into the box), W/(m² sr).
  Color radianceAt(uint32_t k, const Vec3& w) const;
  /// Power leaving exit patch @p k (its radiance integrated over area and projected solid angle), W.
  Color patchPower(uint32_t k) const;

  /// The goniophotometric bin of the unit direction @p w.
  static int gonioBin(const Vec3& w);
  /// The specular light's intensity along the unit direction @p w from the centre, interpolated bilinearly in
  /// (cos θ, φ) between bin centres (constant beyond the first and last θ row), W/sr.
  Color intensityAt(const Vec3& w) const;

  /// True if @p p lies inside the box (its boundary counts as inside).
  bool contains(const Vec3& p) const;
  /// Where the ray from @p o (outside the box) along @p d (not necessarily unit) first enters the box with parameter
  /// t ∈ (0, tmax): @p t and the face @p f crossed. False if it misses the box within tmax or starts inside it.
  bool entry(const Vec3& o, const Vec3& d, float tmax, float& t, int& f) const;
};

/// The outward unit normal of face @p f.
inline Vec3 exitFaceNormal(int f) {
  Vec3 n(0.0f);
  n[f / 2] = (f & 1) ? 1.0f : -1.0f;
  return n;
}

}  // namespace firstshot
