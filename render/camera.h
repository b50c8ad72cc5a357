#pragma once
/// @file camera.h
/// Pinhole camera: image-plane position in pixels -> primary ray. Pixel (0, 0) is the top-left
/// corner of the image; pixel (x, y) covers [x, x+1) × [y, y+1).
#include <cmath>

#include "common/scene_desc.h"
#include "render/ray.h"

namespace fs {

class Camera {
 public:
  explicit Camera(const CameraDesc& c) : width_(c.width), height_(c.height), origin_(c.position) {
    const Vec3d forward = glm::normalize(c.lookAt - c.position);
    const Vec3d right = glm::normalize(glm::cross(forward, c.up));
    const Vec3d up = glm::cross(right, forward);
    const double tanHalf = std::tan(glm::radians(c.fovYDeg) * 0.5);
    const double aspect = double(c.width) / double(c.height);
    forward_ = Vec3(forward);
    // Half extents of the image plane at distance 1.
    right_ = Vec3(right * (tanHalf * aspect));
    up_ = Vec3(up * tanHalf);
  }

  int width() const { return width_; }
  int height() const { return height_; }

  /// Primary ray through the image-plane point (px, py), in pixels; d is unit length.
  Ray generateRay(float px, float py) const {
    const float sx = 2.0f * px / float(width_) - 1.0f;   // -1 left .. +1 right
    const float sy = 1.0f - 2.0f * py / float(height_);  // +1 top .. -1 bottom
    return Ray(origin_, glm::normalize(forward_ + sx * right_ + sy * up_));
  }

 private:
  int width_, height_;
  Vec3 origin_, forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
};

}  // namespace fs
