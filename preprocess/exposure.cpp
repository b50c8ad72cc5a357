#include "preprocess/exposure.h"

#include <cmath>
#include <limits>

namespace fs {

bool ExposureMask::buriedAt(const Vec3d& x) const {
  if (!partial) return false;
  size_t best = 0;
  double bestD = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < points.size(); ++k) {
    const Vec3d d = points[k] - x;
    const double d2 = glm::dot(d, d);
    if (d2 < bestD) bestD = d2, best = k;
  }
  return buried[best] != 0;
}

ExposureCache::ExposureCache(const PatchMesh& mesh, const EmbreeItemBuffer& rays, int grid, int directions)
    : mesh_(mesh), rays_(rays), grid_(grid), once_(new std::once_flag[2 * size_t(mesh.size())]),
      masks_(2 * size_t(mesh.size())) {
  // Stratified cosine-weighted directions: n×n strata, each at its centre.
  const int n = std::max(1, int(std::lround(std::sqrt(double(directions)))));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u = (i + 0.5) / n, v = (j + 0.5) / n;
      const double r = std::sqrt(u), phi = 2.0 * kPi * v;
      directions_.emplace_back(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u)));
    }
  Bounds3d b;
  for (const Patch& p : mesh.patches)
    for (uint32_t k = 0; k < p.count; ++k) b.extend(Vec3d(p.v[k]));
  offset_ = 1e-6 * std::max(b.diagonal(), 1e-30);
}

const ExposureMask& ExposureCache::mask(uint32_t patch, int side) {
  std::call_once(once_[2 * size_t(patch) + side], [&] { compute(patch, side); });
  return masks_[2 * size_t(patch) + side];
}

void ExposureCache::compute(uint32_t patch, int side) {
  const Patch& p = mesh_.patches[patch];
  ExposureMask& m = masks_[2 * size_t(patch) + side];
  // Probe points: the centres of a grid × grid split of each fan triangle's barycentric square.
  const Vec3d a(p.v[0]);
  for (uint32_t t = 1; t + 1 < p.count; ++t) {
    const Vec3d b(p.v[t]), c(p.v[t + 1]);
    for (int j = 0; j < grid_; ++j)
      for (int i = 0; i < grid_; ++i) {
        // Square (u, v) → triangle, area-preserving (u = √ξ1).
        const double su = std::sqrt((i + 0.5) / grid_), v = (j + 0.5) / grid_;
        m.points.push_back(a * (1 - su) + b * (su * (1 - v)) + c * (su * v));
      }
  }
  const Vec3d n = glm::normalize(Vec3d(p.normal)) * (side == 0 ? 1.0 : -1.0);
  const Framed frame(n);
  size_t buried = 0;
  m.buried.assign(m.points.size(), 0);
  for (size_t k = 0; k < m.points.size(); ++k) {
    const Vec3d o = m.points[k] + offset_ * n;
    size_t back = 0;
    for (const Vec3d& l : directions_) {
      const Vec3d d = l.x * frame.s + l.y * frame.t + l.z * frame.n;
      double t = 0;
      const uint32_t hit = rays_.firstHit(o, d, std::numeric_limits<double>::infinity(), t);
      if (hit != kNoPatch && hit != patch && glm::dot(d, Vec3d(mesh_.patches[hit].normal)) > 0) ++back;
    }
    m.buried[k] = 2 * back > directions_.size();
    buried += m.buried[k];
  }
  m.partial = buried > 0 && buried < m.points.size();
}

}  // namespace fs
