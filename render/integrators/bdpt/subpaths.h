#pragma once
/// @file subpaths.h
/// The two subpaths of a bidirectional sample: the camera subpath (a random walk from the
/// pinhole, BSDF sampling in radiance mode with Russian roulette, like the path tracer) and the
/// light subpath (the shared traceLightPath, common/light_path.h, converted), both with their
/// area densities.
#include <vector>

#include "common/sampling/rng.h"
#include "render/integrators/bdpt/densities.h"
#include "render/integrators/common/light_path.h"

namespace firstshot {

/// Traces the camera subpath of @p ray (from the pinhole, unit direction) into @p path (cleared):
/// vertex 0 the pinhole, then up to @p maxHits surface hits; Russian roulette on the throughput
/// once @p rrDepth hits are made. Draws 2 sampler dimensions per bounce, +1 for roulette. Sets the
/// densities (BdptDensities::setDensities). @p rays counts the closest-hit rays.
void traceCameraPath(const BdptDensities& densities, const Ray& ray, int maxHits, int rrDepth, Sampler& sampler,
                     std::vector<SubpathVertex>& path, uint64_t& rays);

/// The bidirectional form of a light subpath of traceLightPath() (empty stays empty): vertex 0 a
/// Kind::Light vertex, densities set (pdfFwd of vertex 0: p_light·p_pos).
void toBdptLightPath(const BdptDensities& densities, const std::vector<LightVertex>& in,
                     std::vector<SubpathVertex>& out);

}  // namespace firstshot
