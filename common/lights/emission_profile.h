#pragma once
/// @file emission_profile.h
/// The relative intensity of a point or spot light (plain cone or IES table) in a WORLD direction,
/// shared by the preprocessor and every integrator so that all see exactly the same emission:
///
///   I(ω) = Φ · profile(ω) / ∫profile dω   (W/sr; Φ = LightDesc::power),
///
/// - point: profile 1, ∫ = 4π;
/// - spot: SpotCone::profile(cos θ) about the axis, in [0, 1];
/// - IES table (LightDesc::ies): the table's candela divided by its largest value, in the frame of
///   LightDesc::direction (the photometric axis) and LightDesc::iesReference (docs/scene-format.md).
/// Direction sampling for emission (light tracing, BDPT): uniform sphere, uniform cone, or the
/// table's piecewise-constant distribution; pdf() returns exactly the density sample() draws from.
#include <cmath>

#include "common/lights/ies.h"
#include "common/lights/spot_cone.h"
#include "common/scene/scene_desc.h"

namespace firstshot {

/// The local frame of an IES light (common/lights/ies.h): Z = axis; type C: X = C0 reference, Y = X × Z;
/// types A/B: Y = up reference, X = Z × Y. The reference defaults to world +x (type C; +z if the
/// axis is along x) or +y (A/B; +z if the axis is along y) and is made orthogonal to the axis.
struct IesFrame {
  Vec3d x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  IesFrame() = default;
  IesFrame(const LightDesc& l) {
    z = glm::normalize(l.direction);
    const bool typeC = !l.ies || l.ies->type == IesType::C;
    Vec3d ref = l.iesReference;
    if (!(glm::length(glm::cross(ref, z)) > 1e-9 * glm::length(ref))) {
      ref = typeC ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
      if (std::abs(glm::dot(ref, z)) > 0.999) ref = Vec3d(0, 0, 1);
    }
    ref = glm::normalize(ref - glm::dot(ref, z) * z);
    if (typeC) x = ref, y = glm::cross(x, z);
    else y = ref, x = glm::cross(z, y);
  }
  Vec3d toLocal(const Vec3d& w) const { return {glm::dot(w, x), glm::dot(w, y), glm::dot(w, z)}; }
  Vec3d toWorld(const Vec3d& d) const { return d.x * x + d.y * y + d.z * z; }
};

/// The emission profile of a point or spot light (see the file comment).
class EmissionProfile {
 public:
  EmissionProfile() = default;  ///< isotropic
  explicit EmissionProfile(const LightDesc& l) {
    if (l.type == LightType::Spot && l.ies) {
      kind_ = Kind::Table, ies_ = l.ies.get(), frame_ = IesFrame(l);
    } else if (l.type == LightType::Spot) {
      kind_ = Kind::Cone, cone_ = SpotCone(l), frame_.z = glm::normalize(l.direction);
    }
  }

  /// Relative intensity in world direction @p w (unit, away from the light); in [0, 1].
  double operator()(const Vec3d& w) const {
    switch (kind_) {
      case Kind::Isotropic: return 1.0;
      case Kind::Cone: return cone_.profile(glm::dot(w, frame_.z));
      case Kind::Table: return ies_->valueLocal(frame_.toLocal(w)) / ies_->maxCandela;
    }
    return 0.0;
  }
  float operator()(const Vec3& w) const { return float((*this)(Vec3d(w))); }

  /// ∫ profile dω over the sphere, sr.
  double integral() const {
    switch (kind_) {
      case Kind::Isotropic: return 4.0 * kPi;
      case Kind::Cone: return cone_.integral();
      case Kind::Table: return ies_->flux / ies_->maxCandela;
    }
    return 0.0;
  }

  /// Intensity Φ·profile(w)/∫profile of light @p l (this profile's light) in direction @p w, W/sr.
  Color intensity(const LightDesc& l, const Vec3d& w) const { return peakIntensity(l) * float((*this)(w)); }
  /// Φ/∫profile: the intensity where the profile is 1, W/sr (0 for a profile of zero solid angle).
  Color peakIntensity(const LightDesc& l) const {
    const double s = integral();
    return s > 0 ? l.power * float(1.0 / s) : Color(0.0f);
  }

  /// The cosine of the half-angle about axis() outside which the profile is 0; −1: the whole sphere.
  double cosCutoff() const { return kind_ == Kind::Cone ? cone_.cosOuter : -1.0; }
  Vec3d axis() const { return frame_.z; }
  bool tabulated() const { return kind_ == Kind::Table; }

  /// A world direction for emission sampling from (@p u0, @p u1) in [0, 1)²; @p pdf receives its
  /// density, 1/sr (0: no direction).
  Vec3d sample(double u0, double u1, double& pdf) const {
    switch (kind_) {
      case Kind::Table: return frame_.toWorld(ies_->sampleLocal(u0, u1, pdf));
      case Kind::Isotropic:
      case Kind::Cone: {
        const double cosMin = cosCutoff(), c = 1.0 - u0 * (1.0 - cosMin), s = std::sqrt(std::max(0.0, 1 - c * c));
        const double phi = 2.0 * kPi * u1;
        pdf = 1.0 / (2.0 * kPi * (1.0 - cosMin));
        const Framed f(frame_.z);
        return s * std::cos(phi) * f.s + s * std::sin(phi) * f.t + c * f.n;
      }
    }
    pdf = 0;
    return frame_.z;
  }
  /// Density of sample() in world direction @p w, 1/sr.
  double pdf(const Vec3d& w) const {
    if (kind_ == Kind::Table) return ies_->pdfLocal(frame_.toLocal(w));
    const double cosMin = cosCutoff();
    return glm::dot(w, frame_.z) >= cosMin ? 1.0 / (2.0 * kPi * (1.0 - cosMin)) : 0.0;
  }

 private:
  enum class Kind { Isotropic, Cone, Table } kind_ = Kind::Isotropic;
  SpotCone cone_;
  const IesData* ies_ = nullptr;  ///< owned by the LightDesc
  IesFrame frame_;
};

}  // namespace firstshot
