// Patches whose grown bounding boxes overlap (patch_neighbours.h).
//
// A uniform grid proposes the pairs: every grown box is listed in each cell it overlaps, the list
// is sorted by cell (a radix sort), and each cell's run of patches is scanned once, every pair in it
// tested. A pair that shares several cells is taken in one of them only: the cell that holds the
// lower corner of the two boxes' intersection. That cell is, along each axis, the first cell of
// one box or the other, and both boxes overlap it; so each entry carries the axes along which its
// cell is the box's first, and a pair counts in a cell where the two together cover all three.
// The pairs then fill the lists by counting, and each list is sorted.
#include "common/patches/patch_neighbours.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace firstshot {

namespace {

/// One cell a patch's grown box overlaps.
struct CellEntry {
  uint64_t cell;   ///< linear cell index (x · ny + y) · nz + z
  uint32_t patch;
  uint32_t firstAxes;  ///< bit a set: the cell is the box's first along axis a
};

/// Sorts @p entries by cell (least significant digit first radix sort over the bits of @p maxCell,
/// in digits of at most 11 bits).
void sortByCell(std::vector<CellEntry>& entries, uint64_t maxCell) {
  int bits = 0;
  while (bits < 64 && (maxCell >> bits) != 0) ++bits;
  const int passes = (bits + 10) / 11, width = passes ? (bits + passes - 1) / passes : 0;
  const uint64_t mask = (uint64_t(1) << width) - 1;
  std::vector<CellEntry> out(entries.size());
  std::vector<size_t> offset(size_t(1) << width);
  for (int shift = 0; shift < passes * width; shift += width) {
    std::fill(offset.begin(), offset.end(), 0);
    for (const CellEntry& e : entries) ++offset[(e.cell >> shift) & mask];
    size_t sum = 0;
    for (size_t& o : offset) sum += std::exchange(o, sum);
    for (const CellEntry& e : entries) out[offset[(e.cell >> shift) & mask]++] = e;
    entries.swap(out);
  }
}

}  // namespace

std::vector<GrownBox> grownPatchBoxes(const PatchMesh& mesh, float& grow) {
  const uint32_t n = mesh.size();
  std::vector<GrownBox> box(n);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t j = r.begin(); j < r.end(); ++j) {
      const Patch& p = mesh.patches[j];
      GrownBox b{p.v[0], p.v[0]};
      for (uint32_t k = 1; k < p.count; ++k) b.lo = glm::min(b.lo, p.v[k]), b.hi = glm::max(b.hi, p.v[k]);
      box[j] = b;
    }
  });
  GrownBox scene{Vec3(INFINITY), Vec3(-INFINITY)};
  for (const GrownBox& b : box) scene.lo = glm::min(scene.lo, b.lo), scene.hi = glm::max(scene.hi, b.hi);
  grow = n > 0 ? 1e-5f * glm::length(scene.hi - scene.lo) : 0.0f;
  for (GrownBox& b : box) b.lo -= grow, b.hi += grow;
  return box;
}

PatchNeighbours patchNeighbours(const PatchMesh& mesh) {
  PatchNeighbours result;
  std::vector<uint64_t>& start = result.start;
  const uint32_t n = mesh.size();
  start.assign(size_t(n) + 1, 0);
  if (n == 0) return result;

  // Boxes, their longest sides (the grown ones') and the scene's box (the boxes' union, grown as they are).
  float grow = 0.0f;
  const std::vector<GrownBox> box = grownPatchBoxes(mesh, grow);
  std::vector<float> extent(n);
  for (uint32_t j = 0; j < n; ++j) {
    const Vec3 e = box[j].hi - box[j].lo;
    extent[j] = std::max(e.x, std::max(e.y, e.z));
  }
  GrownBox scene{Vec3(INFINITY), Vec3(-INFINITY)};
  for (const GrownBox& b : box) scene.lo = glm::min(scene.lo, b.lo), scene.hi = glm::max(scene.hi, b.hi);

  // Cells three times the median patch (twice, or four times, made the 1M-triangle room slower), at
  // least 12 grows (so at most ~8,400 cells along an axis and 2^40 in all).
  std::nth_element(extent.begin(), extent.begin() + n / 2, extent.end());
  float cell = std::max(extent[n / 2], 4.0f * grow) * 3.0f;
  if (!(cell > 0.0f)) cell = 1.0f;  // every patch at one point
  std::vector<float>().swap(extent);
  const Vec3 origin = scene.lo - Vec3(grow);
  auto coord = [&](float x, int axis) { return static_cast<uint64_t>(std::max(0.0f, std::floor((x - origin[axis]) / cell))); };
  const uint64_t ny = coord(scene.hi.y, 1) + 1, nz = coord(scene.hi.z, 2) + 1;
  const uint64_t maxCell = (coord(scene.hi.x, 0) * ny + ny - 1) * nz + nz - 1;
  struct CellRange {
    uint64_t lo[3], hi[3];
    uint64_t count() const { return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1); }
  };
  auto cellsOf = [&](const GrownBox& b) {
    CellRange c;
    for (int a = 0; a < 3; ++a) c.lo[a] = coord(b.lo[a], a), c.hi[a] = coord(b.hi[a], a);
    return c;
  };

  // The (cell, patch) entries, patch j's from entryStart[j] on, then sorted by cell.
  std::vector<uint64_t> entryStart(size_t(n) + 1, 0);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t j = r.begin(); j < r.end(); ++j) entryStart[j + 1] = cellsOf(box[j]).count();
  });
  for (uint32_t j = 0; j < n; ++j) entryStart[j + 1] += entryStart[j];
  std::vector<CellEntry> entries(entryStart[n]);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t j = r.begin(); j < r.end(); ++j) {
      const CellRange c = cellsOf(box[j]);
      CellEntry* e = &entries[entryStart[j]];
      for (uint64_t x = c.lo[0]; x <= c.hi[0]; ++x)
        for (uint64_t y = c.lo[1]; y <= c.hi[1]; ++y)
          for (uint64_t z = c.lo[2]; z <= c.hi[2]; ++z)
            *e++ = {(x * ny + y) * nz + z, j, (x == c.lo[0] ? 1u : 0u) | (y == c.lo[1] ? 2u : 0u) | (z == c.lo[2] ? 4u : 0u)};
    }
  });
  std::vector<uint64_t>().swap(entryStart);
  sortByCell(entries, maxCell);

  // The pairs (in parallel over the runs that begin in a range of entries).
  using Pair = std::pair<uint32_t, uint32_t>;
  struct Member {
    GrownBox box;
    uint32_t patch, firstAxes;
  };
  struct Local {
    std::vector<Pair> pairs;  ///< the first `count` hold pairs
    size_t count = 0;
    std::vector<Member> run;
  };
  tbb::enumerable_thread_specific<Local> locals;
  const size_t m = entries.size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, m, 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
    Local& local = locals.local();
    std::vector<Member>& run = local.run;
    size_t s = r.begin();
    while (s > 0 && s < r.end() && entries[s].cell == entries[s - 1].cell) ++s;
    while (s < r.end()) {
      size_t end = s + 1;
      while (end < m && entries[end].cell == entries[s].cell) ++end;
      if (end - s > 1) {
        run.clear();
        for (size_t u = s; u < end; ++u) run.push_back({box[entries[u].patch], entries[u].patch, entries[u].firstAxes});
        // Without branches (their outcomes are hard to predict): every pair written, the count
        // advanced by the tests.
        for (size_t u = 0; u + 1 < run.size(); ++u) {
          if (local.pairs.size() < local.count + run.size()) local.pairs.resize(2 * (local.count + run.size()));
          const Member& a = run[u];
          Pair* out = local.pairs.data();
          size_t count = local.count;
          for (size_t v = u + 1; v < run.size(); ++v) {
            const Member& b = run[v];
            out[count] = {a.patch, b.patch};
            count += ((a.firstAxes | b.firstAxes) == 7) & a.box.overlaps(b.box);
          }
          local.count = count;
        }
      }
      s = end;
    }
  });
  std::vector<CellEntry>().swap(entries);

  // The lists: counted, filled, sorted.
  for (const Local& local : locals)
    for (size_t i = 0; i < local.count; ++i) ++start[local.pairs[i].first + 1], ++start[local.pairs[i].second + 1];
  for (uint32_t j = 0; j < n; ++j) start[j + 1] += start[j];
  std::vector<uint64_t> fill(start.begin(), start.end() - 1);
  result.adjacent.resize(start[n]);
  for (const Local& local : locals)
    for (size_t i = 0; i < local.count; ++i) {
      const auto [a, b] = local.pairs[i];
      result.adjacent[fill[a]++] = b, result.adjacent[fill[b]++] = a;
    }
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t j = r.begin(); j < r.end(); ++j)
      std::sort(result.adjacent.begin() + int64_t(start[j]), result.adjacent.begin() + int64_t(start[j + 1]));
  });
  return result;
}

}  // namespace firstshot
