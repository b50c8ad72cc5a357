#pragma once
/// @file camera_splat.h
/// A light-subpath vertex joined to the pinhole camera (the t = 1 connection): light tracing's
/// splat of every vertex, and bidirectional path tracing's strategies with one camera vertex.
#include <cstdint>

#include "render/scene/camera.h"
#include "render/integrators/common/light_path.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// The splat of light-path vertex @p v to @p camera, unscaled by 1/N (W/(m² sr) times N):
///     beta · f(ω_light, ω_camera) · |cosθ_x| · W_e·cosθ_c/d²
/// (an area light's vertex 0: beta · cosθ_x · W_e·cosθ_c/d², front side only). False if it
/// cannot reach the pinhole (delta, behind the camera, off the film, occluded, or on the far
/// side). @p pixel receives y·width + x. @p rays counts the shadow ray. @p throughPanes: the shadow ray sees
/// through thin glass with its T(θ) (BDPT, whose camera subpaths cross panes too); false: a pane blocks it
/// (light tracing, which hands a pixel sample whose first hit is a pane to the path tracer: a splat through a
/// pane would count that light twice).
bool connectToCamera(const RenderScene& scene, const LightVertex& v, const Camera& camera, uint32_t& pixel, Color& L,
                     uint64_t& rays, bool throughPanes);

}  // namespace firstshot
