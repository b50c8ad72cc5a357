#pragma once
/// @file luminaire_paths.h
/// Which paths of bidirectional path tracing a luminaire's own lights make (docs/bdpt.md, "Luminaires"). With the
/// luminaires' exit patches among the emitters, light that leaves a luminaire's box after a bounce off a non-delta
/// surface inside it is the exit patches' wherever a strategy with an exit patch can make its path: where, past the
/// box, two neighbouring vertices can be joined (the exit point and the first hit, two non-delta hits, or the last hit
/// and the pinhole). A strategy whose light vertex is that luminaire's light adds nothing for such a path, whichever
/// subpath made which vertex; it makes the others (the camera seeing the inside of a shade, or seeing it in a mirror).
#include <span>

#include "render/integrators/common/subpath_vertex.h"
#include "common/table/luminaire.h"

namespace firstshot {

/// True if the path of light vertices @p light[0 .. s) then camera vertices @p camera[t−1 .. 0] (s = 0: camera vertex
/// t−1 lies on the light), whose light is one of luminaire @p box's, is the exit patches' (above).
bool exitPatchesPath(const Luminaire& box, std::span<const SubpathVertex> light, int s,
                     std::span<const SubpathVertex> camera, int t);

}  // namespace firstshot
