#pragma once
/// @file integrator.h
/// Ray-bundle stochastic iteration as an integrator (`--integrator bundle`): one global transfer
/// (BundleTransfer) per sample index, run by beginPass() before the camera samples of that index,
/// and an image estimate per camera sample; the film's running mean over the iterations is the image.
///
/// Image estimate of iteration k: the camera ray follows delta bounces (mirror, glass; glass branch
/// chosen with the pixel's sampler), each a bounce; emission met at path vertex ≤ maxDepth counts.
/// At the first non-delta hit x (element j, side s facing the eye), path vertex v < maxDepth:
///   2π f_r(x; ω_in, ω_eye)·I_k(j, s)                       the exact BSDF at x, ω_in = ±ω_k on side s,
///                                                          I_k of the orders ≤ maxDepth − 1 − v (BundleTransfer)
///   + PrimaryMode::Exact: NEE (shadow rays, render/lights/next_event.h nextEventEveryLight) to every light the
///     bundle does not carry as emitting geometry: the first-shot table's replaced lights and the
///     kept point, spot and directional lights — their patch-level terms (first-shot, P_k, D_k) stay
///     in the transfer only;
///   + PrimaryMode::Patch: those terms at patch level: the first-shot term at x (FirstShotLighting),
///     2π f_r·P_k(j, s) and f_r(−d, ω_eye)·D_k(l, j) — the paper's plain method without a table.
/// Kept area lights reach x through the bundle in both modes (as in the paper). Both modes
/// therefore converge to the same solution as path tracing at the same max depth (up to
/// BundleTransfer::kMaxOrders; deeper: every bounce), up to the patch discretisation of the
/// global part (and, for Patch, of the direct light of the point-like lights).
#include <cstdint>
#include <vector>

#include "render/lights/next_event.h"
#include "render/firstshot/lighting.h"
#include "render/integrators/integrator.h"
#include "render/integrators/bundle/transfer.h"

namespace firstshot {

class BundleIntegrator : public PassIntegrator {
 public:
  explicit BundleIntegrator(const IntegratorOptions& options) : options_(options) {}
  /// Settings for the next preprocess().
  void setSettings(const BundleSettings& settings) { settings_ = settings; }
  const BundleSettings& settings() const { return settings_; }

  void preprocess(const RenderScene& scene) override;
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  std::string name() const override { return "bundle"; }
  /// Brings the transfer to iteration @p sampleIndex: one iteration when called for successive
  /// indices; a restart from iteration 0 (same seed: the same states) when the index goes back
  /// or the seed changes.
  void beginPass(int sampleIndex, uint64_t seed) const override;

  /// The transfer's state after the last beginPass().
  const BundleTransfer& transfer() const { return transfer_; }

 private:
  /// The radiance leaving a non-delta hit, path vertex @p vertex (< maxDepth), towards the eye
  /// (everything but its own emission): the transfer's light of orders ≤ maxDepth − 1 − @p vertex.
  Color surface(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf, int vertex,
                Sampler& sampler, uint64_t& rays) const;

  IntegratorOptions options_;
  BundleSettings settings_;
  const RenderScene* scene_ = nullptr;
  FirstShotLighting firstShot_;
  std::vector<uint8_t> neeLights_;  ///< by LightSet index: sampled by NEE with PrimaryMode::Exact
  bool anyNee_ = false;
  // The global state changes only between passes (beginPass), never while Li() runs.
  mutable BundleTransfer transfer_;
  mutable uint64_t seed_ = 0;
};

}  // namespace firstshot
