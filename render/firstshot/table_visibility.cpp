// Visibility of the small lights from the patches, certain where the patch and its neighbours agree
// (table_visibility.h).
#include "render/firstshot/table_visibility.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/patches/patch_neighbours.h"
#include "render/scene/ray.h"
#include "render/scene/table_rows.h"

namespace firstshot {

void TableVisibilityMap::build(const FirstShotTable& t, const std::vector<float>& visible, const std::vector<LightDesc>& lights) {
  const uint32_t n = t.mesh.size();
  sampleOfLight_.assign(lights.size(), kNoId);
  std::vector<uint8_t> single(t.samples.size(), 0);
  for (size_t i = 0; i < t.samples.size(); ++i) {
    const LightSample& s = t.samples[i];
    if ((s.kind == LightSampleKind::Point || s.kind == LightSampleKind::Spot) && s.light < lights.size() &&
        (lights[s.light].type == LightType::Point || lights[s.light].type == LightType::Spot)) {
      sampleOfLight_[s.light] = static_cast<uint32_t>(i);
      single[i] = 1;
    }
  }
  start_.clear();
  entries_.clear();
  if (std::find(single.begin(), single.end(), 1) == single.end()) return;  // no point or spot light: Unknown
  const PatchNeighbours nb = patchNeighbours(t.mesh);
  const std::vector<uint64_t>& nStart = nb.start;
  const std::vector<uint32_t>& adjacent = nb.adjacent;
  // Per factor: its sample, with kWhole set where the patch sees it whole; kNoId for the samples
  // that are not one point or spot light.
  const TableRows rows(t);
  std::vector<uint32_t> code(rows.factors());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, code.size()), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const uint32_t i = rows.at(k).sample;
      code[k] = !single[i] ? kNoId : i | (std::abs(visible[k] - 1.0f) <= kVisibleTolerance ? kWhole : 0u);
    }
  });
  // Per patch: the samples of its own row and its neighbours' rows, each with the number of those
  // patches that see it whole (dense counters per thread, reset through the list of samples touched).
  // The entries of a block of patches go one after the other into the block's list.
  struct Counters {
    std::vector<uint32_t> present, whole, touched;
  };
  tbb::enumerable_thread_specific<Counters> counters;
  constexpr uint32_t kBlock = 4096;
  std::vector<std::vector<uint32_t>> blocks((n + kBlock - 1) / kBlock);
  start_.assign(size_t(n) + 1, 0);
  tbb::parallel_for(size_t(0), blocks.size(), [&](size_t block) {
    Counters& c = counters.local();
    if (c.present.empty()) c.present.assign(t.samples.size(), 0), c.whole.assign(t.samples.size(), 0);
    std::vector<uint32_t>& out = blocks[block];
    uint32_t *present = c.present.data(), *whole = c.whole.data();
    auto add = [&](uint32_t patch) {
      for (const TableFactor f : rows[patch]) {
        const uint32_t e = code[f.index], i = e & ~kWhole;
        if (e == kNoId) continue;
        if (present[i]++ == 0) c.touched.push_back(i);
        whole[i] += e >> 31;
      }
    };
    for (uint32_t j = uint32_t(block * kBlock); j < std::min(n, uint32_t((block + 1) * kBlock)); ++j) {
      add(j);
      for (uint64_t a = nStart[j]; a < nStart[j + 1]; ++a) add(adjacent[a]);
      std::sort(c.touched.begin(), c.touched.end());
      const uint32_t patches = static_cast<uint32_t>(nStart[j + 1] - nStart[j]) + 1;
      for (const uint32_t i : c.touched) {
        out.push_back(i | (c.whole[i] == patches ? kWhole : 0u));
        c.present[i] = c.whole[i] = 0;
      }
      start_[j + 1] = c.touched.size();
      c.touched.clear();
    }
  });
  for (uint32_t j = 0; j < n; ++j) start_[j + 1] += start_[j];
  entries_.resize(start_[n]);
  tbb::parallel_for(size_t(0), blocks.size(), [&](size_t block) {
    std::copy(blocks[block].begin(), blocks[block].end(), entries_.begin() + int64_t(start_[block * kBlock]));
  });
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

}  // namespace firstshot
