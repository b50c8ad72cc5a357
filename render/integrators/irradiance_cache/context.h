#pragma once
/// @file context.h
/// Private to the irradiance cache integrator's sources: the state of one camera sample or fill
/// task, and how a ray was chosen (which decides whether the emission it meets counts).
#include <cstdint>
#include <memory>

#include "render/integrators/irradiance_cache/integrator.h"

namespace firstshot {

struct IrradianceCacheIntegrator::Context {
  /// Shared: new records go into the shared cache. Private: into @c overlay, seen only by this
  /// context (two-pass: fill tasks, whose records are merged later, and read-only rendering).
  enum class Mode : uint8_t { Shared, Private };
  explicit Context(Mode m) : mode(m) {}
  Mode mode;
  std::unique_ptr<IrradianceCache> overlay;  ///< private records (created on the first one)
  uint64_t rays = 0;
  uint64_t lookups = 0;  ///< irradiance lookups in the cache (a fill task that made none met no surface it serves)
};

enum class IrradianceCacheIntegrator::RayKind : uint8_t {
  Camera,  ///< from the camera: emission counts
  Delta,   ///< after a mirror or glass bounce: emission counts (no light sampling could find it)
  Gather,  ///< a hemisphere sample of the primary method: only gathered (large) lights count
  Glossy,  ///< a BSDF sample of the non-diffuse part: gathered lights with MIS, small lights not
};

/// What radiance() reports of a ray's first vertex (for the primary method).
struct IrradianceCacheIntegrator::FirstVertex {
  float distance = 0.0f;   ///< to the first hit, m (infinity: the ray escaped)
  Hit hit;                 ///< the first hit (valid if distance is finite)
  Color firstShot{0.0f};   ///< first-shot term of the first hit, included in the radiance (W/(m² sr))
};

}  // namespace firstshot
