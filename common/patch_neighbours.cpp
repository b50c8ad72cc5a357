// Patches whose grown bounding boxes overlap (patch_neighbours.h).
#include "common/patch_neighbours.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace fs {

namespace {

struct Box {
  Vec3 lo{0.0f}, hi{0.0f};
  bool overlaps(const Box& b) const { return glm::all(glm::lessThanEqual(lo, b.hi)) && glm::all(glm::lessThanEqual(b.lo, hi)); }
};

}  // namespace

PatchNeighbours patchNeighbours(const PatchMesh& mesh) {
  PatchNeighbours result;
  std::vector<uint64_t>& start = result.start;
  std::vector<uint32_t>& adjacent = result.adjacent;
  const uint32_t n = mesh.size();
  std::vector<Box> box(n);
  Box scene{Vec3(INFINITY), Vec3(-INFINITY)};
  std::vector<float> extent(n);
  for (uint32_t j = 0; j < n; ++j) {
    const Patch& p = mesh.patches[j];
    Box b{p.v[0], p.v[0]};
    for (uint32_t k = 1; k < p.count; ++k) b.lo = glm::min(b.lo, p.v[k]), b.hi = glm::max(b.hi, p.v[k]);
    box[j] = b;
    scene.lo = glm::min(scene.lo, b.lo), scene.hi = glm::max(scene.hi, b.hi);
    const Vec3 e = b.hi - b.lo;
    extent[j] = std::max(e.x, std::max(e.y, e.z));
  }
  start.assign(size_t(n) + 1, 0);
  if (n == 0) return result;
  const float grow = 1e-5f * glm::length(scene.hi - scene.lo);
  for (Box& b : box) b.lo -= grow, b.hi += grow;
  std::vector<float> sorted = extent;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const float cell = std::max(sorted[n / 2], 4.0f * grow) * 2.0f;
  // (cell key, patch) for every cell a grown box overlaps; boxes sharing a cell are candidates.
  std::vector<std::pair<uint64_t, uint32_t>> cells;
  auto coord = [&](float x, float lo) { return static_cast<uint64_t>(std::max(0.0f, std::floor((x - lo) / cell))); };
  const Vec3 origin = scene.lo - Vec3(2.0f * grow);
  // Calls f(key) for every cell box b overlaps.
  auto forCells = [&](const Box& b, auto&& f) {
    const uint64_t x0 = coord(b.lo.x, origin.x), x1 = coord(b.hi.x, origin.x);
    const uint64_t y0 = coord(b.lo.y, origin.y), y1 = coord(b.hi.y, origin.y);
    const uint64_t z0 = coord(b.lo.z, origin.z), z1 = coord(b.hi.z, origin.z);
    for (uint64_t x = x0; x <= x1; ++x)
      for (uint64_t y = y0; y <= y1; ++y)
        for (uint64_t z = z0; z <= z1; ++z) f((x << 42) | (y << 21) | z);
  };
  for (uint32_t j = 0; j < n; ++j) forCells(box[j], [&](uint64_t key) { cells.emplace_back(key, j); });
  std::sort(cells.begin(), cells.end());
  // Per patch (in parallel): the patches sharing one of its cells whose boxes overlap its own.
  std::vector<std::vector<uint32_t>> lists(n);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t j) {
    const Box& b = box[j];
    std::vector<uint32_t>& list = lists[j];
    forCells(b, [&](uint64_t key) {
      auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key, uint32_t(0)));
      for (; it != cells.end() && it->first == key; ++it)
        if (it->second != j && b.overlaps(box[it->second])) list.push_back(it->second);
    });
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  });
  for (uint32_t j = 0; j < n; ++j) start[j + 1] = start[j] + lists[j].size();
  adjacent.resize(start[n]);
  for (uint32_t j = 0; j < n; ++j) std::copy(lists[j].begin(), lists[j].end(), adjacent.begin() + int64_t(start[j]));
  return result;
}

}  // namespace fs
