#pragma once
/// @file strategies.h
/// The unweighted contributions of the strategies (s, t) with t ≥ 2 (a camera subpath of at
/// least one hit): s = 0 the camera subpath meets an area light, s = 1 a new light sample is
/// joined to camera vertex t−1 (next-event estimation), s ≥ 2 light vertex s−1 is joined to camera
/// vertex t−1 by a shadow ray. t = 1 (light vertices joined to the pinhole) is the shared
/// connectToCamera (render/integrators/common/camera_splat.h). All in W/(m² sr) (camera throughput ×
/// radiance).
#include <span>

#include "common/sampling/rng.h"
#include "render/integrators/bdpt/densities.h"

namespace firstshot {

/// s = 0: the emitted radiance of camera vertex t−1 towards vertex t−2, times its throughput: an
/// area light's front side that the emission sampler emits from, or (table mode, if @p patchEmits)
/// a lit patch's first-shot radiance; 0 otherwise.
Color connectEmission(const BdptDensities& densities, const SubpathVertex& pt, bool patchEmits);

/// s = 1: samples a light vertex with the emission sampler's light choice and position (one
/// next2Dd pair, always drawn: the choice's remainder places the point) into @p sampled and joins it to @p pt. 0 if @p pt is delta,
/// the light sends nothing towards it, or the segment is blocked. @p rays counts the shadow ray.
Color connectLightSample(const BdptDensities& densities, const SubpathVertex& pt, Sampler& sampler,
                         SubpathVertex& sampled, uint64_t& rays);

/// s ≥ 2, t ≥ 2: light vertex @p qs joined to camera vertex @p pt (0 if either is delta or the
/// segment is blocked). @p rays counts the shadow ray.
Color connectVertices(const BdptDensities& densities, const SubpathVertex& qs, const SubpathVertex& pt,
                      uint64_t& rays);

}  // namespace firstshot
