#pragma once
/// @file exit_emission.h
/// Particles leaving the luminaires' exit patches with their exit distribution (common/table/luminaire.h), for light
/// tracing (render/integrators/light/integrator.h): the light of a luminaire's lights from where it leaves the box
/// for the first time. Exit patches are numbered as LuminaireBoxes numbers them across all luminaires.
///
/// On exit patch k: a point uniform by area (density 1/A_k), a direction bin b chosen by its power (the bin's radiance
/// L_b, mean RGB, times π/kBins times A_k: probability q_b = mean(L_b)/Σ_b' mean(L_b')), and a direction uniform in
/// (sin²θ, φ) inside the bin, i.e. uniform in projected solid angle there (each bin covers π/kBins of it): solid-angle
/// density q_b·kBins·cosθ/π. With the patch chosen by its power P_k = Σ_b mean(L_b)·A_k·π/kBins out of a total P, a
/// particle's power L_b·cosθ/(p_patch·p_pos·p_dir) is P·L_b/mean(L_b): the same for every exit particle, up to its
/// bin's colour.
#include <cstdint>
#include <vector>

#include "common/sampling/distribution_1d.h"
#include "common/table/luminaire.h"
#include "common/util/math.h"
#include "render/scene/luminaire_boxes.h"

namespace firstshot {

/// One direction leaving an exit patch: ExitEmission::sampleDirection.
struct ExitDirection {
  Vec3 d{0.0f};         ///< unit direction, out of the box
  Color radiance{0.0f};  ///< the exit radiance along d (its bin's), W/(m² sr)
  float pdf = 0.0f;      ///< solid-angle density of d, 1/sr
};

class ExitEmission {
 public:
  ExitEmission() = default;
  /// The exit patches of @p boxes (which, with the luminaires it points to, must outlive this object).
  explicit ExitEmission(const LuminaireBoxes& boxes);

  /// Number of exit patches (LuminaireBoxes::exitCount).
  uint32_t count() const { return uint32_t(patches_.size()); }
  /// The luminaires whose exit patches these are (null before construction from them).
  const LuminaireBoxes* boxes() const { return boxes_; }
  /// Exit patch @p e's rectangle.
  const ExitPatch& patch(uint32_t e) const { return patches_[e]; }
  /// Power leaving exit patch @p e (mean RGB of Luminaire::patchPower), W.
  double power(uint32_t e) const { return power_[e]; }
  /// A direction leaving exit patch @p e: its bin by power with @p uBin ∈ [0,1), its point in the bin's
  /// (sin²θ, φ) rectangle with @p uDir. False if the patch sends nothing (or the sample grazes the face).
  bool sampleDirection(uint32_t e, double uBin, const Vec2& uDir, ExitDirection& out) const;
  /// The solid-angle density with which sampleDirection() draws the unit direction @p d from exit patch @p e, 1/sr
  /// (0 into the box).
  float pdfDirection(uint32_t e, const Vec3& d) const;
  /// The radiance leaving exit patch @p e along the unit direction @p d (its bin's; 0 into the box), W/(m² sr).
  Color radiance(uint32_t e, const Vec3& d) const;

 private:
  const LuminaireBoxes* boxes_ = nullptr;
  std::vector<ExitPatch> patches_;  ///< by exit patch
  std::vector<double> power_;       ///< by exit patch, W (mean RGB)
  /// By exit patch: its kBins direction bins by power (unused for a patch that sends nothing). Double: a faint bin's
  /// share is then exact enough that every particle's power is the same (a float CDF's differences would be off by
  /// up to 1e-7 absolute).
  std::vector<Distribution1D> bins_;
};

}  // namespace firstshot
