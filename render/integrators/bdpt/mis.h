#pragma once
/// @file mis.h
/// The multiple-importance-sampling weight of one bidirectional strategy (power heuristic over all
/// strategies that could have sampled the same path; Veach 1997, ch. 10; docs/bdpt.md).
#include <span>

#include "render/integrators/bdpt/densities.h"

namespace firstshot {

/// Power-heuristic weight of strategy (s, t): the path light[0..s−1] + camera[t−1..0] (light
/// vertices s and on, camera vertices t and on, are not read). For s = 1, light[0] is the light
/// vertex sampled for the connection. The connection vertices' reverse densities are evaluated
/// here; every other density is the subpaths' own. Strategies that need a connection through a
/// delta vertex (BSDF, or the light's position or direction) and t = 0 (the pinhole cannot be hit)
/// are left out of the sum; s + t = 2 has weight 1 (the area light seen directly is strategy (0, 2)
/// alone).
float misWeight(const BdptDensities& densities, std::span<const SubpathVertex> light,
                std::span<const SubpathVertex> camera, int s, int t);

}  // namespace firstshot
