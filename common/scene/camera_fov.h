#pragma once
/// @file camera_fov.h
/// A pinhole camera's field of view on each image axis, and a change of resolution that keeps the field on the axis
/// the scene fixed (CameraDesc::fovAxis): a Mitsuba sensor with `fov_axis x` keeps its horizontal field when only the
/// aspect changes, as Mitsuba itself would render the scene with that film; a JSON camera keeps its vertical field.
#include "common/scene/scene_desc.h"

namespace firstshot {

/// tan(θ/2) on @p axis over tan(θy/2) on the vertical axis, for a film of aspect @p aspect (width / height, > 0):
/// 1 on y, the aspect on x, √(1 + aspect²) on the diagonal; smaller and larger pick y or x by the aspect (x when
/// the film is square).
double fovAxisScale(FovAxis axis, double aspect);

/// The vertical field of view, degrees, of a film of aspect @p aspect whose field of view on @p axis is
/// @p fovDeg degrees (in (0, 180)).
double verticalFov(FovAxis axis, double fovDeg, double aspect);

/// The field of view of camera @p c on @p axis, degrees.
double fovOnAxis(const CameraDesc& c, FovAxis axis);

/// Gives @p c the resolution @p width × @p height (each ≥ 1) with the same field of view on c.fovAxis: fovYDeg is
/// recomputed for the new aspect (unchanged for FovAxis::Y or an unchanged aspect).
void resizeCamera(CameraDesc& c, int width, int height);

}  // namespace firstshot
