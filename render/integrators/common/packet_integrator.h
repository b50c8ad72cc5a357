#pragma once
/// @file packet_integrator.h
/// A sampling integrator (IntegratorKind::Sampling) whose estimate along a camera ray may start from
/// the ray's closest hit, traced already: Li() traces that hit itself, LiBlock() traces a 4 × 4
/// block's camera rays as one Embree packet (3× the rays per second of single rays) and starts each
/// wanted ray from its hit. The path tracer and the irradiance cache are such integrators; each
/// writes LiFrom() only, so the packet loop is written once.
#include <cstdint>

#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace firstshot {

class PacketIntegrator : public Integrator {
 public:
  /// LiFrom() with the first hit traced here.
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const final;
  /// The block's traced rays as one packet, then LiFrom() per wanted ray that hits (background() for one that misses).
  void LiBlock(const Ray* rays, const bool* traced, const bool* wanted, int count, Sampler* samplers,
               SampleInfo* infos, Color* L) const final;

 protected:
  /// Radiance arriving at the camera along @p ray (as Li()). @p first: the ray's closest hit when
  /// the caller traced it already (and counted it in @p rays), null for LiFrom() to trace it.
  /// @p rays counts the rays traced; @p info, if given, receives the AOVs.
  virtual Color LiFrom(const Ray& ray, const Hit* first, Sampler& sampler, SampleInfo* info,
                       uint64_t& rays) const = 0;

  /// What a camera ray that misses the scene sees along @p dir: the infinite light's radiance (0 without one).
  Color background(const Vec3& dir) const;

  const RenderScene* scene_ = nullptr;  ///< the scene, kept by the integrator's preprocess()
};

}  // namespace firstshot
