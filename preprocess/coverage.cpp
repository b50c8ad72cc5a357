#include "preprocess/coverage.h"

#include <algorithm>
#include <cmath>

#include "common/analytic.h"

namespace fs {
namespace {

/// Sutherland–Hodgman: keeps the part of a convex polygon where dot(p − origin, n) ≥ offset.
int clipToPlane(const Vec3d* in, int n, const Vec3d& origin, const Vec3d& normal, double offset, Vec3d* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3d& a = in[i];
    const Vec3d& b = in[(i + 1) % n];
    const double da = glm::dot(a - origin, normal) - offset, db = glm::dot(b - origin, normal) - offset;
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m;
}

}  // namespace

double coveredWeight(const View& view, const std::vector<double>& weights, const Vec3d* poly, int count, double near,
                     size_t& pixels) {
  pixels = 0;
  Vec3d clipped[8];
  const bool persp = view.projection == Projection::Perspective;
  const int n = clipToPlane(poly, count, view.eye, view.forward, persp ? near : 0.0, clipped);
  if (n < 3) return 0.0;
  // Image-plane coordinates of the clipped polygon.
  Vec2d q[8];
  Vec2d lo(1e300), hi(-1e300);
  for (int i = 0; i < n; ++i) {
    const Vec3d r = clipped[i] - view.eye;
    const double z = persp ? glm::dot(r, view.forward) : 1.0;
    q[i] = Vec2d(glm::dot(r, view.right) / z, glm::dot(r, view.up) / z);
    lo = glm::min(lo, q[i]), hi = glm::max(hi, q[i]);
  }
  // Orientation, so that "inside" means the same side of every edge.
  double area2 = 0;
  for (int i = 0; i < n; ++i) area2 += q[i].x * q[(i + 1) % n].y - q[(i + 1) % n].x * q[i].y;
  if (area2 == 0) return 0.0;
  const double sign = area2 > 0 ? 1.0 : -1.0;
  // Pixel index range whose centres may fall inside.
  const double du = (view.planeMax.x - view.planeMin.x) / view.width, dv = (view.planeMax.y - view.planeMin.y) / view.height;
  const int i0 = std::max(0, int(std::floor((lo.x - view.planeMin.x) / du - 0.5)));
  const int i1 = std::min(view.width - 1, int(std::ceil((hi.x - view.planeMin.x) / du - 0.5)));
  const int j0 = std::max(0, int(std::floor((view.planeMax.y - hi.y) / dv - 0.5)));
  const int j1 = std::min(view.height - 1, int(std::ceil((view.planeMax.y - lo.y) / dv - 0.5)));
  double sum = 0;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const Vec2d c = view.pixelCentre(i, j);
      bool inside = true;
      for (int e = 0; e < n && inside; ++e) {
        const Vec2d a = q[e], b = q[(e + 1) % n];
        inside = sign * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) >= 0;
      }
      if (!inside) continue;
      const double w = weights[size_t(j) * view.width + i];
      if (w > 0) sum += w, ++pixels;
    }
  }
  return sum;
}

double unoccludedSolidAngle(const Vec3d& eye, const Vec3d* poly, int count) {
  double s = 0;
  for (int i = 1; i + 1 < count; ++i) s += analytic::solidAngleTriangle(eye, poly[0], poly[i], poly[i + 1]);
  return s;
}

double unoccludedCosineSolidAngle(const Vec3d& eye, const Vec3d& n, const Vec3d* poly, int count) {
  Vec3d clipped[8];
  const int m = clipToPlane(poly, count, eye, n, 0.0, clipped);
  if (m < 3) return 0.0;
  return kPi * analytic::pointPolygonFormFactor(eye, n, std::vector<Vec3d>(clipped, clipped + m));
}

double unoccludedProjectedArea(const Vec3d& direction, const Vec3d* poly, int count) {
  Vec3d cross(0.0);
  for (int i = 1; i + 1 < count; ++i) cross += glm::cross(poly[i] - poly[0], poly[i + 1] - poly[0]);
  return 0.5 * std::abs(glm::dot(cross, glm::normalize(direction)));
}

}  // namespace fs
