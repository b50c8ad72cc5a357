#pragma once
/// @file camera.h
/// Pinhole camera: image-plane position in pixels -> primary ray. Pixel (0, 0) is the top-left
/// corner of the image; pixel (x, y) covers [x, x+1) × [y, y+1).
#include <cmath>

#include "common/scene/scene_desc.h"
#include "render/scene/ray.h"

namespace firstshot {

/// Where a scene point lands on the film of a pinhole camera, and the importance it receives
/// (the camera side of a light-tracing connection).
struct CameraConnection {
  Vec2 raster{0.0f};     ///< image-plane position in pixels (pixel (x, y) covers [x, x+1) × [y, y+1))
  Vec3 wi{0.0f};         ///< unit direction from the point to the pinhole
  float distance = 0;    ///< from the point to the pinhole, m
  /// W_e(ω)·cosθ_c/d² for the pixel hit, in 1/m² (per unit solid angle → per unit area of the point):
  /// W_e = 1/(A_pixel·cos⁴θ_c) with A_pixel the pixel's area on the image plane at unit distance
  /// (REFERENCE.md, adjoint identity; the box filter of the jittered camera rays). A point's
  /// contribution to its pixel is then (radiance-like weight)·|cosθ_x|·importance.
  float importance = 0;
};

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

  /// The pinhole, m.
  const Vec3& position() const { return origin_; }

  /// Projects @p p onto the film (the inverse of generateRay). @return false when @p p is behind
  /// the camera or outside the image.
  bool connect(const Vec3& p, CameraConnection& out) const {
    const Vec3 d = origin_ - p;
    const float dist2 = glm::dot(d, d);
    const float z = -glm::dot(d, forward_);  // depth along the view axis
    if (!(z > 0.0f) || !(dist2 > 0.0f)) return false;
    const Vec3 q = -d / z;  // on the image plane at unit distance
    const float sx = glm::dot(q, right_) / glm::dot(right_, right_), sy = glm::dot(q, up_) / glm::dot(up_, up_);
    out.raster = Vec2((sx + 1.0f) * 0.5f * float(width_), (1.0f - sy) * 0.5f * float(height_));
    if (!(out.raster.x >= 0.0f && out.raster.x < float(width_) && out.raster.y >= 0.0f && out.raster.y < float(height_)))
      return false;
    out.distance = std::sqrt(dist2);
    out.wi = d / out.distance;
    const float cosC = z / out.distance;
    const float pixelArea = 4.0f * glm::length(right_) * glm::length(up_) / (float(width_) * float(height_));
    out.importance = 1.0f / (pixelArea * cosC * cosC * cosC * dist2);
    return true;
  }

 private:
  int width_, height_;
  Vec3 origin_, forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
};

}  // namespace firstshot
