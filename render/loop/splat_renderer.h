#pragma once
/// @file splat_renderer.h
/// The render loop of splatting integrators (IntegratorKind::Splatting, e.g. light tracing), called by
/// render() for them. Pass k (= sample index k) traces the integrator's particles in fixed chunks
/// of kSplatChunk particles, in parallel; the chunks' splats are then summed into the pass image
/// in chunk order (a sequential merge), and every pixel receives one film sample: its splat sum
/// plus the integrator's Li() for a camera ray keyed like the gathering integrators' (seed, pixel, k).
/// The image is therefore bit-identical for any number of threads, and passes 0..n−1 rendered
/// one at a time give the same film as one render of n samples.
#include "render/loop/renderer.h"

namespace firstshot {

/// Particles per parallel work item; part of the output contract only through the merge order
/// (any value gives the same image, since the merge is in particle order).
inline constexpr uint64_t kSplatChunk = 1024;

/// render() for a splatting integrator: same options, same statistics (cameraSamples counts the
/// pixel samples; rays include the particles' rays; nonFinite counts NaN/Inf splats and pixel samples).
RenderStats renderSplatting(const SplattingIntegrator& integrator, const Camera& camera, Film& film,
                            const RenderOptions& options);

}  // namespace firstshot
