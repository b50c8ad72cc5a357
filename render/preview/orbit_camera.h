#pragma once
/// @file orbit_camera.h
/// The preview's interactive camera: orbit around a target, pan, dolly and fly, on the scene's
/// pinhole camera (position, look-at point, up, vertical field of view). Until it is moved it
/// returns the scene's camera unchanged, bit for bit, so the preview renders the offline image.
#include <algorithm>
#include <cmath>

#include "common/scene/scene_desc.h"

namespace firstshot {

class OrbitCamera {
 public:
  explicit OrbitCamera(const CameraDesc& c) : desc_(c) {}

  /// The camera as the renderer takes it.
  const CameraDesc& desc() const { return desc_; }
  double distance() const { return glm::length(desc_.lookAt - desc_.position); }
  Vec3d forward() const { return glm::normalize(desc_.lookAt - desc_.position); }
  Vec3d right() const { return glm::normalize(glm::cross(forward(), desc_.up)); }

  /// Turns the camera around the look-at point by @p yaw radians about the up vector and by
  /// @p pitch radians about the right vector; pitch stops 1° short of looking along up.
  void orbit(double yaw, double pitch) {
    const Vec3d up = glm::normalize(desc_.up);
    Vec3d offset = rotate(desc_.position - desc_.lookAt, up, -yaw);
    const Vec3d r = glm::normalize(glm::cross(-offset, up));
    const Vec3d pitched = rotate(offset, r, pitch);
    const double limit = std::cos(glm::radians(1.0));
    if (std::abs(glm::dot(glm::normalize(pitched), up)) < limit) offset = pitched;
    desc_.position = desc_.lookAt + offset;
  }

  /// Moves camera and look-at point within the image plane so that the look-at plane follows a
  /// cursor displacement of (@p dx, @p dy) pixels (y down) in an image @p heightPx pixels tall.
  void pan(double dx, double dy, double heightPx) {
    const double perPixel = 2.0 * distance() * std::tan(glm::radians(desc_.fovYDeg) * 0.5) / heightPx;
    const Vec3d r = right(), u = glm::cross(r, forward());
    const Vec3d delta = (-dx * r + dy * u) * perPixel;
    desc_.position += delta;
    desc_.lookAt += delta;
  }

  /// Moves towards the look-at point by the fraction 1 − 0.9^@p steps of the distance (away for
  /// negative steps); never closer than @p minDistance.
  void dolly(double steps, double minDistance) {
    const double d = distance();
    const double nd = std::max(minDistance, d * std::pow(0.9, steps));
    desc_.position = desc_.lookAt - forward() * nd;
  }

  /// Translates camera and look-at point along forward, right and up by the given metres.
  void fly(double alongForward, double alongRight, double alongUp) {
    const Vec3d f = forward(), r = right(), u = glm::cross(r, f);
    const Vec3d delta = alongForward * f + alongRight * r + alongUp * u;
    desc_.position += delta;
    desc_.lookAt += delta;
  }

 private:
  /// Rodrigues' rotation of @p v by @p angle about the unit @p axis.
  static Vec3d rotate(const Vec3d& v, const Vec3d& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0 - c);
  }

  CameraDesc desc_;
};

}  // namespace firstshot
