// Visibility factors for the light trees' top levels (LightSampler::buildVisibility).
//
// A light tree chooses by bounds of power, distance and orientation; it cannot know that the
// bulbs of a cove, the inside of a lamp shade or the lights of the next room are hidden from a
// point. Here, once per scene, a few shadow rays from surface points in each cell of a coarse
// grid to the emitters under each node of the tree's cut at depth D estimate the share v that
// is visible; the descent then weights those nodes by ε + (1 − ε)·v. The factors depend on the
// cell only, so sample() and pmf() agree exactly; ε > 0 keeps every emitter reachable, so the
// estimator stays unbiased whatever the estimate.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/patches/patches.h"
#include "common/sampling/distribution_1d.h"
#include "common/sampling/rng.h"
#include "render/lights/light_sampler.h"

namespace firstshot {

namespace {

constexpr int kGridCells = 32;       ///< cells along the scene's longest side
constexpr int kCutDepth = 7;         ///< the factors weight the nodes down to this depth (≤ 128 per cut)
constexpr int kPointsPerCell = 3;    ///< receiver points per cell (patch or piece centroids), each used on both sides
constexpr int kRaysPerNode = 6;      ///< shadow rays from a cell to the emitters under one cut node, at most
constexpr double kRayBudget = 1.0e6; ///< rays per tree at most (fewer per node in large scenes, at least 2)
constexpr float kEpsilon = 0.05f;    ///< floor of the factor: a node never loses more than 20× its chance
constexpr uint64_t kSeed = 0x5eed1e55ull;

struct Receiver {
  Vec3 p{0.0f}, n{0.0f};
};

}  // namespace

void LightSampler::buildVisibility() {
  const PatchMesh& mesh = scene_->mesh();
  if (mesh.size() == 0) return;
  Vec3d lo, hi;
  scene_->desc().bounds(lo, hi);
  const Vec3 extent = Vec3(hi - lo);
  const float longest = std::max({extent.x, extent.y, extent.z});
  if (!(longest > 0.0f)) return;
  // Shared by the trees (and by the copies of this sampler: a light sampler kept in the scene's memo).
  const auto shared = std::make_shared<VisibilityGrid>();
  VisibilityGrid& grid = *shared;
  grid.cell = longest / float(kGridCells);
  if (std::isfinite(mesh.patchSize)) grid.cell = std::max(grid.cell, float(mesh.patchSize));
  grid.origin = Vec3(lo);
  grid.nx = std::max(1, int(std::ceil(extent.x / grid.cell)));
  grid.ny = std::max(1, int(std::ceil(extent.y / grid.cell)));
  grid.nz = std::max(1, int(std::ceil(extent.z / grid.cell)));
  grid.row.assign(size_t(grid.nx) * grid.ny * grid.nz, -1);

  // Receivers: in every cell that a patch's bounds touch, the centroids of the kPointsPerCell
  // such patches with the smallest hash of their ID (a deterministic, spread-out choice).
  // A patch longer than a cell (a face traced whole, without a table) offers the centroids of its
  // cell-sized pieces instead of its own, so every cell it crosses gets points of its own.
  // Per cell (a flat array over the grid): its candidates ordered by key, equal keys in the order
  // they came, the first kPointsPerCell kept.
  struct Candidate {
    uint64_t key;
    Receiver r;
  };
  struct Chosen {
    Candidate c[kPointsPerCell];
    int count = 0;
    void offer(const Candidate& candidate) {
      int at = count;
      while (at > 0 && c[at - 1].key > candidate.key) --at;
      if (at == kPointsPerCell) return;
      for (int m = std::min(count, kPointsPerCell - 1); m > at; --m) c[m] = c[m - 1];
      c[at] = candidate;
      count = std::min(count + 1, kPointsPerCell);
    }
  };
  std::vector<Chosen> chosen(grid.row.size());
  std::vector<std::vector<Vec3d>> pieces;
  std::vector<size_t> cells;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& patch = mesh.patches[j];
    Vec3d v[4];
    double longestEdge = 0;
    for (uint32_t i = 0; i < patch.count; ++i) v[i] = Vec3d(patch.v[i]);
    for (uint32_t i = 0; i < patch.count; ++i) longestEdge = std::max(longestEdge, glm::length(v[(i + 1) % patch.count] - v[i]));
    const bool whole = !(longestEdge > grid.cell * (1 + 1e-4));  // (a patch of the size the cell was made from stays whole)
    if (!whole) {
      pieces.clear();
      subdividePolygon(v, int(patch.count), grid.cell, pieces);
    }
    const size_t pieceCount = whole ? 1 : pieces.size();
    for (size_t k = 0; k < pieceCount; ++k) {
      const Vec3d* piece = whole ? v : pieces[k].data();
      const size_t corners = whole ? patch.count : pieces[k].size();
      Vec3 plo(piece[0]), phi = plo;
      Vec3d centroid(0.0);
      for (size_t i = 0; i < corners; ++i)
        plo = glm::min(plo, Vec3(piece[i])), phi = glm::max(phi, Vec3(piece[i])), centroid += piece[i];
      const Receiver r{pieceCount == 1 ? patch.centroid : Vec3(centroid / double(corners)), patch.normal};
      const uint64_t key = pieceCount == 1 ? hashKeys(kSeed, j) : hashKeys(kSeed, j, k);
      const Vec3 step(grid.cell);
      cells.clear();
      for (float z = plo.z; z < phi.z + step.z; z += step.z)
        for (float y = plo.y; y < phi.y + step.y; y += step.y)
          for (float x = plo.x; x < phi.x + step.x; x += step.x)
            cells.push_back(grid.cellOf(glm::min(Vec3(x, y, z), phi)));
      std::sort(cells.begin(), cells.end());
      cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
      for (size_t cell : cells) chosen[cell].offer({key, r});
    }
  }
  std::vector<std::vector<Receiver>> receivers;
  for (size_t cell = 0; cell < chosen.size(); ++cell) {
    if (chosen[cell].count == 0) continue;
    grid.row[cell] = static_cast<int32_t>(receivers.size());
    receivers.emplace_back();
    for (int m = 0; m < chosen[cell].count; ++m) receivers.back().push_back(chosen[cell].c[m].r);
  }
  grid.rows = receivers.size();
  const float offset = 1e-4f * glm::length(extent);

  for (Group& g : groups_) {
    if (g.emitters.size() < 2 || g.tree.empty()) continue;
    const int D = std::min(kCutDepth, g.tree.depth());
    const std::vector<uint32_t> cut = g.tree.cut(D);
    // The emitters under each cut node, with a power CDF to choose ray targets.
    std::vector<std::vector<uint32_t>> members(cut.size());
    std::vector<Distribution1Df> byPower(cut.size());
    for (size_t k = 0; k < cut.size(); ++k) {
      std::vector<float> power;
      g.tree.emittersUnder(cut[k], members[k], power);
      byPower[k] = Distribution1Df(std::vector<double>(power.begin(), power.end()));
    }
    const int rays = int(std::clamp(kRayBudget / double(grid.rows * cut.size()), 2.0, double(kRaysPerNode)));
    std::vector<float> v(grid.rows * cut.size(), 1.0f);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.rows), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t r = range.begin(); r < range.end(); ++r)
        for (size_t k = 0; k < cut.size(); ++k) {
          if (members[k].empty()) continue;
          Sampler sampler(kSeed, r, k);
          float visible = 0.0f;  // rays that reach the emitter, a pane's transmittance counted as a fraction
          for (int m = 0; m < rays; ++m) {
            const Receiver& rc = receivers[r][size_t(m) % receivers[r].size()];
            const Vec3 q = rc.p + ((m / int(receivers[r].size())) % 2 == 0 ? offset : -offset) * rc.n;
            const float u = sampler.next1D();
            const size_t i = byPower[k].sampleDiscrete(u);
            const Vec3 y = emitterPoint(g.emitters[members[k][i]], sampler.next2D());
            const Vec3 d = y - q;
            const float dist = glm::length(d);
            if (!(dist > 0.0f)) {
              visible += 1.0f;
              continue;
            }
            const Color through = scene_->transmittance(Ray(q, d / dist, 0.0f, dist * (1.0f - 1e-3f)));
            visible += (through.x + through.y + through.z) * (1.0f / 3.0f);
          }
          v[r * cut.size() + k] = visible / float(rays);
        }
    });
    g.tree.setVisibility(shared, D, v, kEpsilon);
  }
}

}  // namespace firstshot
