#include "preprocess/exposure.h"


#include <algorithm>
#include <cmath>
#include <limits>

#include "common/patches/patch_neighbours.h"

namespace firstshot {

bool ExposureQuery::buried(const Vec3d& x) const {
  if (!mask || !mask->partial) return false;
  return mask->cells ? cache->cell(patch, side, *mask, x) : cache->nearest(patch, side, *mask, x);
}

ExposureCache::ExposureCache(const PatchMesh& mesh, const EmbreeItemBuffer& rays, const EmbreeItemBuffer& probeRays,
                             int grid, int directions)
    : mesh_(mesh), rays_(rays), probeRays_(probeRays), grid_(grid), once_(new std::once_flag[2 * size_t(mesh.size())]),
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
  // Patches met by a patch outside their plane: the only ones that can be partly buried. "Met" as
  // patch_neighbours.h has it (bounding boxes grown by 1e-5 of the mesh's diagonal overlap), found by a point query
  // of the ray caster's BVH about each grown box, which stops at the first patch out of the plane: about a tenth of
  // the time of listing every pair (the classroom's 120,000 patches have 11 million pairs); asked only of the patches
  // whose masks are wanted (met()).
  planeTolerance_ = 1e-5 * std::max(b.diagonal(), 1e-30);
  boxes_ = grownPatchBoxes(mesh, grow_);
}

bool ExposureCache::met(uint32_t j) const {
  const Patch& p = mesh_.patches[j];
  const Vec3d normal = glm::normalize(Vec3d(p.normal));
  const auto outOfPlane = [&](uint32_t i) {
    if (i == j || !boxes_[j].overlaps(boxes_[i])) return false;
    const Patch& q = mesh_.patches[i];
    bool inPlane = std::abs(glm::dot(normal, glm::normalize(Vec3d(q.normal)))) >= 1.0 - 1e-6;
    for (uint32_t k = 0; k < q.count && inPlane; ++k)
      inPlane = std::abs(glm::dot(Vec3d(q.v[k]) - Vec3d(p.v[0]), normal)) <= planeTolerance_;
    return !inPlane;
  };
  // The ball about the grown box, widened by another grow: a patch whose grown box meets this one's has its
  // triangles' boxes within it.
  const float radius = 0.5f * glm::length(boxes_[j].hi - boxes_[j].lo) * (1.0f + 1e-5f) + 2.0f * grow_;
  return rays_.anyPatchNear(0.5f * (boxes_[j].lo + boxes_[j].hi), radius, outOfPlane);
}

const ExposureMask& ExposureCache::mask(uint32_t patch, int side) {
  std::call_once(once_[2 * size_t(patch) + side], [&] { compute(patch, side); });
  return masks_[2 * size_t(patch) + side];
}

void ExposureCache::compute(uint32_t patch, int side) {
  const Patch& p = mesh_.patches[patch];
  ExposureMask& m = masks_[2 * size_t(patch) + side];
  if (!met(patch)) return;  // nothing meets it: exposed or buried whole, never partly (exposure.h)
  // Probe points, evenly spread: cell centres of a grid × grid bilinear split of a quad, centroids of
  // the grid² sub-triangles of a triangle.
  const Vec3d v0(p.v[0]), v1(p.v[1]), v2(p.v[2]), v3(p.v[p.count == 4 ? 3 : 2]);
  for (int j = 0; j < grid_; ++j)
    for (int i = 0; i < grid_; ++i) {
      if (p.count == 4) {
        const double u = (i + 0.5) / grid_, v = (j + 0.5) / grid_;
        m.points.push_back((1 - u) * (1 - v) * v0 + u * (1 - v) * v1 + u * v * v2 + (1 - u) * v * v3);
      } else if (i + j < grid_) {  // upward sub-triangle (i, j), and the downward one beside it
        const auto at = [&](double a, double b) { return v0 + (a / grid_) * (v1 - v0) + (b / grid_) * (v2 - v0); };
        m.points.push_back(at(i + 1.0 / 3, j + 1.0 / 3));
        if (i + j + 1 < grid_) m.points.push_back(at(i + 2.0 / 3, j + 2.0 / 3));
      }
    }
  size_t buried = 0;
  m.buried.assign(m.points.size(), 0);
  for (size_t k = 0; k < m.points.size(); ++k) {
    m.buried[k] = probe(patch, side, m.points[k]);
    buried += m.buried[k];
  }
  m.partial = buried > 0 && buried < m.points.size();
  // Border probes: a disagreeing probe within 1.5 grid steps (a step: the longest side or
  // diagonal of the patch / grid).
  double step = 0;
  for (uint32_t k = 0; k < p.count; ++k)
    for (uint32_t l = k + 1; l < p.count; ++l) step = std::max(step, glm::length(Vec3d(p.v[l]) - Vec3d(p.v[k])));
  const double r2 = (1.5 * step / grid_) * (1.5 * step / grid_);
  m.border.assign(m.points.size(), 0);
  if (m.partial)
    for (size_t k = 0; k < m.points.size(); ++k)
      for (size_t l = 0; l < m.points.size() && !m.border[k]; ++l) {
        const Vec3d d = m.points[k] - m.points[l];
        m.border[k] = m.buried[k] != m.buried[l] && glm::dot(d, d) <= r2;
      }
  if (!m.partial) return;
  // The lattice over the patch's bounding rectangle in its plane.
  const Framed frame(glm::normalize(Vec3d(p.normal)));
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  for (uint32_t k = 0; k < p.count; ++k) {
    const Vec3d r = Vec3d(p.v[k]) - v0;
    const double a = glm::dot(r, frame.s), b = glm::dot(r, frame.t);
    lo[0] = std::min(lo[0], a), hi[0] = std::max(hi[0], a), lo[1] = std::min(lo[1], b), hi[1] = std::max(hi[1], b);
  }
  m.h = step / (grid_ * kLatticePerStep);
  if (!(m.h > 0)) return;
  m.s = frame.s, m.t = frame.t, m.origin = v0 + lo[0] * frame.s + lo[1] * frame.t;
  m.nu = std::max(1, int(std::ceil((hi[0] - lo[0]) / m.h))), m.nv = std::max(1, int(std::ceil((hi[1] - lo[1]) / m.h)));
  m.cells.reset(new std::atomic<uint8_t>[size_t(m.nu) * m.nv]);
  for (size_t c = 0; c < size_t(m.nu) * m.nv; ++c) m.cells[c].store(0, std::memory_order_relaxed);
}

bool ExposureCache::nearest(uint32_t patch, int side, const ExposureMask& m, const Vec3d& x) const {
  size_t best = 0;
  double bestD = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < m.points.size(); ++k) {
    const Vec3d d = m.points[k] - x;
    const double d2 = glm::dot(d, d);
    if (d2 < bestD) bestD = d2, best = k;
  }
  return m.border[best] ? probe(patch, side, x) : m.buried[best] != 0;
}

bool ExposureCache::cell(uint32_t patch, int side, const ExposureMask& m, const Vec3d& x) const {
  const Vec3d r = x - m.origin;
  const int i = std::clamp(int(std::floor(glm::dot(r, m.s) / m.h)), 0, m.nu - 1);
  const int j = std::clamp(int(std::floor(glm::dot(r, m.t) / m.h)), 0, m.nv - 1);
  std::atomic<uint8_t>& c = m.cells[size_t(j) * m.nu + i];
  uint8_t state = c.load(std::memory_order_relaxed);
  if (state == 0) {  // two threads may both decide a new cell; they store the same answer
    state = nearest(patch, side, m, m.origin + (i + 0.5) * m.h * m.s + (j + 0.5) * m.h * m.t) ? 2 : 1;
    c.store(state, std::memory_order_relaxed);
  }
  return state == 2;
}

bool ExposureCache::probe(uint32_t patch, int side, const Vec3d& x) const {
  const Vec3d n = glm::normalize(Vec3d(mesh_.patches[patch].normal)) * (side == 0 ? 1.0 : -1.0);
  const Framed frame(n);
  const Vec3d o = x + offset_ * n;
  // Buried: more than half of the rays hit a back face. Traced in packets of 8, stopping as soon as the vote is
  // decided (the same answer as tracing every ray).
  const size_t total = directions_.size();
  size_t back = 0, traced = 0;
  Vec3d d[8];
  uint32_t hits[8];
  while (traced < total) {
    const size_t count = std::min<size_t>(8, total - traced);
    for (size_t k = 0; k < count; ++k) {
      const Vec3d& l = directions_[traced + k];
      d[k] = l.x * frame.s + l.y * frame.t + l.z * frame.n;
    }
    probeRays_.firstHits(o, d, count, hits);
    for (size_t k = 0; k < count; ++k)
      if (hits[k] != kNoPatch && hits[k] != patch && glm::dot(d[k], Vec3d(mesh_.patches[hits[k]].normal)) > 0) ++back;
    traced += count;
    if (2 * back > total) return true;
    if (2 * (back + (total - traced)) <= total) return false;
  }
  return 2 * back > total;
}

}  // namespace firstshot
