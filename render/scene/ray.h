#pragma once
/// @file ray.h
/// A ray with its valid parameter interval, and what the renderer learns about a hit.
#include <cstdint>
#include <limits>

#include "common/util/math.h"

namespace firstshot {

/// Ray o + t·d for t in [tmin, tmax]; d need not be normalised (t is then in units of |d|).
struct Ray {
  Vec3 o{0.0f};
  Vec3 d{0.0f, 0.0f, 1.0f};
  float tmin = 0.0f;
  float tmax = std::numeric_limits<float>::infinity();

  Ray() = default;
  Ray(const Vec3& o_, const Vec3& d_, float tmin_ = 0.0f, float tmax_ = std::numeric_limits<float>::infinity())
      : o(o_), d(d_), tmin(tmin_), tmax(tmax_) {}
  Vec3 at(float t) const { return o + t * d; }
};

inline constexpr uint32_t kNoId = 0xffffffffu;

/// The closest hit of a ray. Exactly one of @c patch and @c emitter is set (the other is kNoId).
struct Hit {
  float t = 0.0f;          ///< ray parameter
  Vec3 p{0.0f};            ///< hit point
  Vec3 ng{0.0f, 0.0f, 1.0f};  ///< unit geometric normal of the front side (right-hand rule over the vertices)
  uint32_t patch = kNoId;  ///< patch ID (index into the PatchMesh) when the hit is on the patch mesh
  uint32_t emitter = kNoId;   ///< emitter mesh index when the hit is on an area light
  uint32_t triangle = kNoId;  ///< emitter: triangle index within that emitter mesh
  /// Distance to move a new ray's origin off the surface (scaled to the coordinates' magnitude).
  float eps = 1e-5f;

  bool onPatch() const { return patch != kNoId; }
  /// Origin for a ray leaving the surface in direction @p w: offset along ±ng to the side of w.
  Vec3 spawnOrigin(const Vec3& w) const { return p + (glm::dot(w, ng) >= 0.0f ? eps : -eps) * ng; }
};

}  // namespace firstshot
