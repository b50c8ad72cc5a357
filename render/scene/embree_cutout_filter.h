#pragma once
/// @file embree_cutout_filter.h
/// Alpha cut-outs in the renderer's Embree scene (common/patches/patch_cutouts.h): a geometry filter on the
/// patch geometry, for closest hits and occlusion alike, that rejects a candidate hit where the surface is absent.
/// Embree calls it for candidate hits in any order, and rejecting is all it does, so the closest hit that remains
/// is the closest existing one; the context filters (thin glass, allHits) only see the hits it accepted. Installed
/// only when the scene has cut-outs: other scenes trace without any filter.
#include <embree3/rtcore.h>

#include "common/patches/patch_cutouts.h"

namespace firstshot {

/// Installs the cut-out filter on the patch geometry @p g (primitive = patch ID) for intersection and occlusion;
/// @p cutouts must outlive the geometry.
void installCutoutFilter(RTCGeometry g, const PatchCutouts& cutouts);

}  // namespace firstshot
