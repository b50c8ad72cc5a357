// The unoccluded integral of a spot's kernel over a patch (common/lights/spot_integral.h).
#include "common/lights/spot_integral.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

double spotPatchIntegral(const LightSample& s, const EmissionProfile& profile, const Patch& p, int side) {
  Vec3d poly[4];
  for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
  double diameter = 0;
  for (uint32_t k = 0; k < p.count; ++k)
    for (uint32_t l = k + 1; l < p.count; ++l) diameter = std::max(diameter, glm::length(poly[l] - poly[k]));
  const Vec3d light(s.position);
  const Vec3d n = glm::normalize(Vec3d(p.normal)) * (side == 0 ? 1.0 : -1.0);
  const double dist = glm::length(light - Vec3d(p.centroid));
  const int m = dist < 2.0 * diameter ? 32 : dist < 8.0 * diameter ? 12 : 4;
  double sum = 0;
  for (uint32_t t = 0; t + 2 < p.count; ++t) {
    const Vec3d a = poly[0], b = poly[t + 1], e = poly[t + 2];
    const double area = 0.5 * glm::length(glm::cross(b - a, e - a));
    double tri = 0;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        // The cell centres of a uniform map of the unit square onto the triangle.
        const double u = (i + 0.5) / m, v = (j + 0.5) / m, su = std::sqrt(u);
        const Vec3d x = (1.0 - su) * a + su * (1.0 - v) * b + su * v * e;
        const Vec3d r = light - x;
        const double d2 = glm::dot(r, r);
        if (!(d2 > 0)) continue;
        const double inv = 1.0 / std::sqrt(d2), cosX = glm::dot(r, n) * inv;
        if (!(cosX > 0)) continue;
        tri += cosX / d2 * profile(-r * inv);
      }
    sum += area * tri / double(m * m);
  }
  return sum;
}

}  // namespace firstshot
