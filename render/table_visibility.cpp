// Visibility of the small lights from the patches, certain where the patch and its neighbours agree
// (table_visibility.h).
#include "render/table_visibility.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace fs {

namespace {

struct Box {
  Vec3 lo{0.0f}, hi{0.0f};
  bool overlaps(const Box& b) const { return glm::all(glm::lessThanEqual(lo, b.hi)) && glm::all(glm::lessThanEqual(b.lo, hi)); }
};

/// Per patch, the other patches whose boxes (grown by 10⁻⁵ of the scene's diagonal) overlap its own:
/// CSR in @p start / @p adjacent. A uniform grid of cells about the median patch size proposes pairs.
void neighbours(const PatchMesh& mesh, std::vector<uint64_t>& start, std::vector<uint32_t>& adjacent) {
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
  adjacent.clear();
  if (n == 0) return;
  const float grow = 1e-5f * glm::length(scene.hi - scene.lo);
  for (Box& b : box) b.lo -= grow, b.hi += grow;
  std::vector<float> sorted = extent;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const float cell = std::max(sorted[n / 2], 4.0f * grow) * 2.0f;
  // (cell key, patch) for every cell a grown box overlaps; boxes sharing a cell are candidates.
  std::vector<std::pair<uint64_t, uint32_t>> cells;
  auto coord = [&](float x, float lo) { return static_cast<uint64_t>(std::max(0.0f, std::floor((x - lo) / cell))); };
  const Vec3 origin = scene.lo - Vec3(2.0f * grow);
  for (uint32_t j = 0; j < n; ++j) {
    const Box& b = box[j];
    const uint64_t x0 = coord(b.lo.x, origin.x), x1 = coord(b.hi.x, origin.x);
    const uint64_t y0 = coord(b.lo.y, origin.y), y1 = coord(b.hi.y, origin.y);
    const uint64_t z0 = coord(b.lo.z, origin.z), z1 = coord(b.hi.z, origin.z);
    for (uint64_t x = x0; x <= x1; ++x)
      for (uint64_t y = y0; y <= y1; ++y)
        for (uint64_t z = z0; z <= z1; ++z) cells.emplace_back((x << 42) | (y << 21) | z, j);
  }
  std::sort(cells.begin(), cells.end());
  // Per patch (in parallel): the patches sharing one of its cells whose boxes overlap its own.
  std::vector<std::vector<uint32_t>> lists(n);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t j) {
    const Box& b = box[j];
    std::vector<uint32_t>& list = lists[j];
    const uint64_t x0 = coord(b.lo.x, origin.x), x1 = coord(b.hi.x, origin.x);
    const uint64_t y0 = coord(b.lo.y, origin.y), y1 = coord(b.hi.y, origin.y);
    const uint64_t z0 = coord(b.lo.z, origin.z), z1 = coord(b.hi.z, origin.z);
    for (uint64_t x = x0; x <= x1; ++x)
      for (uint64_t y = y0; y <= y1; ++y)
        for (uint64_t z = z0; z <= z1; ++z) {
          const uint64_t key = (x << 42) | (y << 21) | z;
          auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key, uint32_t(0)));
          for (; it != cells.end() && it->first == key; ++it)
            if (it->second != j && b.overlaps(box[it->second])) list.push_back(it->second);
        }
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  });
  for (uint32_t j = 0; j < n; ++j) start[j + 1] = start[j] + lists[j].size();
  adjacent.resize(start[n]);
  for (uint32_t j = 0; j < n; ++j) std::copy(lists[j].begin(), lists[j].end(), adjacent.begin() + int64_t(start[j]));
}

}  // namespace

void TableVisibilityMap::build(const FirstShotTable& t, const std::vector<float>& visible, size_t sceneLights) {
  const uint32_t n = t.mesh.size();
  sampleOfLight_.assign(sceneLights, kNoId);
  std::vector<uint8_t> single(t.samples.size(), 0);
  for (size_t i = 0; i < t.samples.size(); ++i) {
    const LightSample& s = t.samples[i];
    if ((s.kind == LightSampleKind::Point || s.kind == LightSampleKind::Spot) && s.light < sceneLights) {
      sampleOfLight_[s.light] = static_cast<uint32_t>(i);
      single[i] = 1;
    }
  }
  std::vector<uint64_t> nStart;
  std::vector<uint32_t> adjacent;
  neighbours(t.mesh, nStart, adjacent);
  // Per patch: the samples of its own row and its neighbours' rows, each with the number of those
  // patches that see it whole (dense counters per thread, reset through the list of samples touched).
  struct Counters {
    std::vector<uint32_t> present, whole, touched;
  };
  tbb::enumerable_thread_specific<Counters> counters;
  std::vector<std::vector<uint32_t>> rows(n);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t j) {
    Counters& c = counters.local();
    if (c.present.empty()) c.present.assign(t.samples.size(), 0), c.whole.assign(t.samples.size(), 0);
    auto add = [&](uint32_t patch) {
      for (uint64_t k = t.rowStart[patch]; k < t.rowStart[patch + 1]; ++k) {
        const uint32_t i = t.sampleIndex[k];
        if (!single[i]) continue;
        if (c.present[i]++ == 0) c.touched.push_back(i);
        c.whole[i] += std::abs(visible[k] - 1.0f) <= kVisibleTolerance;
      }
    };
    add(j);
    for (uint64_t a = nStart[j]; a < nStart[j + 1]; ++a) add(adjacent[a]);
    std::sort(c.touched.begin(), c.touched.end());
    const uint32_t patches = static_cast<uint32_t>(nStart[j + 1] - nStart[j]) + 1;
    std::vector<uint32_t>& row = rows[j];
    row.reserve(c.touched.size());
    for (const uint32_t i : c.touched) {
      row.push_back(i | (c.whole[i] == patches ? kWhole : 0u));
      c.present[i] = c.whole[i] = 0;
    }
    c.touched.clear();
  });
  start_.assign(size_t(n) + 1, 0);
  for (uint32_t j = 0; j < n; ++j) start_[j + 1] = start_[j] + rows[j].size();
  entries_.resize(start_[n]);
  for (uint32_t j = 0; j < n; ++j) std::copy(rows[j].begin(), rows[j].end(), entries_.begin() + int64_t(start_[j]));
}

TableVisibility TableVisibilityMap::query(uint32_t patch, uint32_t light) const { return cursor(patch).next(light); }

TableVisibilityMap::Cursor TableVisibilityMap::cursor(uint32_t patch) const {
  Cursor c;
  if (patch + 1 >= start_.size()) return c;
  c.map_ = this;
  c.begin_ = c.at_ = entries_.data() + start_[patch];
  c.end_ = entries_.data() + start_[patch + 1];
  return c;
}

TableVisibility TableVisibilityMap::Cursor::next(uint32_t light) {
  if (!map_ || light >= map_->sampleOfLight_.size() || map_->sampleOfLight_[light] == kNoId)
    return TableVisibility::Unknown;
  const uint32_t i = map_->sampleOfLight_[light];
  if (at_ > begin_ && (at_[-1] & ~kWhole) >= i) at_ = begin_;  // the lights came out of order: start again
  while (at_ < end_ && (*at_ & ~kWhole) < i) ++at_;
  if (at_ == end_ || (*at_ & ~kWhole) != i) return TableVisibility::Hidden;
  return (*at_ & kWhole) ? TableVisibility::Visible : TableVisibility::Unknown;
}

}  // namespace fs
