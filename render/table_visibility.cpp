// Visibility of the small lights from the patches, certain where the patch and its neighbours agree
// (table_visibility.h).
#include "render/table_visibility.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/patch_neighbours.h"

namespace fs {

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
  const PatchNeighbours nb = patchNeighbours(t.mesh);
  const std::vector<uint64_t>& nStart = nb.start;
  const std::vector<uint32_t>& adjacent = nb.adjacent;
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
  if (patch + 1 >= start_.size() || entries_.empty()) return c;  // no point or spot light anywhere: Unknown
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
