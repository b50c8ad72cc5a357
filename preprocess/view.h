#pragma once
/// @file view.h
/// A camera for item buffers (perspective or orthographic) and the axis-aligned bounds that fix its
/// near and far planes. Both item-buffer back ends sample exactly the pixel centres defined here.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "common/util/math.h"

namespace firstshot {

/// Axis-aligned box in double precision.
struct Bounds3d {
  Vec3d lo{std::numeric_limits<double>::infinity()};
  Vec3d hi{-std::numeric_limits<double>::infinity()};

  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  void extend(const Vec3d& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  Vec3d centre() const { return 0.5 * (lo + hi); }
  /// Length of the diagonal (0 for an empty box).
  double diagonal() const { return empty() ? 0.0 : glm::length(hi - lo); }
  Vec3d corner(int i) const { return {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z}; }
};

enum class Projection : uint8_t { Perspective, Orthographic };

/// An item-buffer camera. The basis (right, up, forward) is orthonormal; the camera looks along forward.
///
/// Image plane: perspective views have it at focal distance 1 in front of the eye, orthographic views
/// through the eye; in both cases it spans [planeMin.x, planeMax.x] × [planeMin.y, planeMax.y] in
/// (right, up) coordinates (metres for orthographic views).
///
/// Pixel order (both back ends): row-major, @c ids[j*width + i]; column i = 0 is the left edge
/// (planeMin.x), row j = 0 is the TOP edge (planeMax.y). Pixel (i, j) samples its centre only.
///
/// Depth is measured along forward: for perspective views a point at eye + d·(forward + u·right + v·up)
/// has depth d, so the near plane is the plane at depth @c near (not a sphere).
struct View {
  Vec3d eye{0.0};
  Vec3d right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, 1};
  Projection projection = Projection::Perspective;
  Vec2d planeMin{-1, -1}, planeMax{1, 1};
  int width = 0, height = 0;

  size_t pixelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  /// Image-plane coordinates (u, v) of the centre of pixel (i, j).
  Vec2d pixelCentre(int i, int j) const {
    return {planeMin.x + (i + 0.5) * (planeMax.x - planeMin.x) / width,
            planeMax.y - (j + 0.5) * (planeMax.y - planeMin.y) / height};
  }
  /// Area of one pixel on the image plane (focal plane for perspective views, m² for orthographic).
  double pixelArea() const {
    return (planeMax.x - planeMin.x) * (planeMax.y - planeMin.y) / (static_cast<double>(width) * height);
  }
  /// Ray origin through pixel (i, j): the eye (perspective) or the pixel on the image plane (orthographic).
  Vec3d pixelOrigin(int i, int j) const {
    if (projection == Projection::Perspective) return eye;
    const Vec2d uv = pixelCentre(i, j);
    return eye + uv.x * right + uv.y * up;
  }
  /// Ray direction through pixel (i, j), NOT normalised: its forward component is 1, so the ray
  /// parameter equals depth.
  Vec3d pixelDirection(int i, int j) const {
    if (projection == Projection::Orthographic) return forward;
    const Vec2d uv = pixelCentre(i, j);
    return forward + uv.x * right + uv.y * up;
  }
};

/// Largest depth of the box seen from @p view (≤ 0 when the box is entirely behind the eye),
/// enlarged slightly so that the farthest corner is still inside the far plane.
inline double farDepth(const View& view, const Bounds3d& bounds) {
  if (bounds.empty()) return 0.0;
  double far = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 8; ++i) far = std::max(far, glm::dot(bounds.corner(i) - view.eye, view.forward));
  return far + 1e-3 * bounds.diagonal();
}

}  // namespace firstshot
