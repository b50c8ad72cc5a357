// A pinhole camera's field of view per image axis (common/scene/camera_fov.h).
#include "common/scene/camera_fov.h"

#include <cmath>

namespace firstshot {

double fovAxisScale(FovAxis axis, double aspect) {
  switch (axis) {
    case FovAxis::Y: return 1.0;
    case FovAxis::X: return aspect;
    case FovAxis::Diagonal: return std::sqrt(1.0 + aspect * aspect);
    case FovAxis::Smaller: return aspect > 1.0 ? 1.0 : aspect;  // wider than tall: y is the smaller axis
    case FovAxis::Larger: return aspect > 1.0 ? aspect : 1.0;
  }
  return 1.0;
}

double verticalFov(FovAxis axis, double fovDeg, double aspect) {
  const double t = std::tan(glm::radians(fovDeg) * 0.5) / fovAxisScale(axis, aspect);
  return glm::degrees(2.0 * std::atan(t));
}

double fovOnAxis(const CameraDesc& c, FovAxis axis) {
  const double aspect = double(c.width) / double(c.height);
  return glm::degrees(2.0 * std::atan(std::tan(glm::radians(c.fovYDeg) * 0.5) * fovAxisScale(axis, aspect)));
}

void resizeCamera(CameraDesc& c, int width, int height) {
  const double kept = fovOnAxis(c, c.fovAxis);
  const bool sameAspect = int64_t(width) * c.height == int64_t(height) * c.width;
  c.width = width, c.height = height;
  if (c.fovAxis != FovAxis::Y && !sameAspect) c.fovYDeg = verticalFov(c.fovAxis, kept, double(width) / double(height));
}

}  // namespace firstshot
