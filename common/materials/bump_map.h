#pragma once
/// @file bump_map.h
/// OBJ/MTL bump maps (`bump`, `map_bump`: assimp's HEIGHT texture) as normal maps. A bump image is either a
/// height map, turned here into a tangent-space normal map, or already a normal map (Blender's OBJ exporter writes
/// normal maps as `map_Bump`), told by its colours.
///
/// Height to normal: with h the image's first channel (linear, rows from the top, so row y + 1 is further along v)
/// and per-texel central differences (the image's edges wrap), the tangent-space normal is
///     n = normalize(−s·∂h/∂x, −s·∂h/∂y, 1),  ∂h/∂x = (h(x+1, y) − h(x−1, y))/2,  ∂h/∂y = (h(x, y+1) − h(x, y−1))/2,
/// s the MTL `-bm` multiplier where assimp reports it (assimp 5.2's OBJ reader does not: 1), stored as a normal map's texel (n + 1)/2 in the frame the renderer decodes
/// normal maps in (render/scene/shading_normals.h: x along +u, y along +v): the surface tilts away from where it
/// rises, by atan(s × the height step per texel).
#include "common/materials/texture.h"

namespace firstshot {

/// Whether the bump image @p im is a normal map: its mean colour has blue above 0.6 and red and green within 0.15
/// of 0.5 (a height map is grey: equal channels).
bool bumpImageIsNormalMap(const TexelImage& im);

/// The tangent-space normal map of the height image @p heights with multiplier @p scale (above).
TexelImage normalMapFromHeights(const TexelImage& heights, float scale);

}  // namespace firstshot
