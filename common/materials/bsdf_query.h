#pragma once
/// @file bsdf_query.h
/// One BSDF query (directions in the local shading frame, the transport mode, the sample's results), the
/// argument of every model's sample/eval/pdf (common/materials/bsdf.h), in a header of its own so that the models
/// declared in other headers (thin_glass.h, rough_dielectric.h) need not include bsdf.h, which includes them.

#include <cstdint>

#include "common/util/math.h"

namespace firstshot {

/// Which quantity a path carries: radiance (paths from the camera) or importance (paths from the
/// lights). Only refraction differs: radiance is scaled by 1/η² across an interface.
enum class TransportMode : uint8_t { Radiance, Importance };

/// Arguments and results of one BSDF query. All directions are in the local shading frame.
struct BSDFQuery {
  Vec3 wo{0.0f, 0.0f, 1.0f};  ///< in: unit direction towards the viewer / previous vertex
  Vec3 wi{0.0f, 0.0f, 1.0f};  ///< in for eval/pdf; out of sample: towards the light / next vertex
  float pdf = 0.0f;           ///< out of sample: solid-angle density of wi (discrete probability for a delta lobe), 0 on failure
  bool specular = false;      ///< out of sample: wi was chosen by a delta lobe
  float eta = 1.0f;           ///< out of sample: relative index η(wi side)/η(wo side); 1 unless refracted
  TransportMode mode = TransportMode::Radiance;  ///< in

  BSDFQuery() = default;
  explicit BSDFQuery(const Vec3& wo_, TransportMode mode_ = TransportMode::Radiance) : wo(wo_), mode(mode_) {}
  BSDFQuery(const Vec3& wi_, const Vec3& wo_, TransportMode mode_ = TransportMode::Radiance)
      : wo(wo_), wi(wi_), mode(mode_) {}
};

/// Marks @p q as a failed sample (no direction drawn) and returns its zero weight.
inline Color failedSample(BSDFQuery& q) {
  q.pdf = 0.0f;
  q.specular = false;
  q.eta = 1.0f;
  return Color(0.0f);
}

}  // namespace firstshot
