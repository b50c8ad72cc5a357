// Grouped factors: splitting a table's rows into singles and (light, V) groups, and expanding them back.
#include "common/table/firstshot_groups.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <mutex>
#include <span>

#include "common/lights/form_factors.h"

namespace firstshot {
namespace {

/// The area-vertex samples of each light that has some: CSR over those lights.
struct LightVertices {
  std::vector<uint32_t> light;   ///< the lights that have area vertices, ascending (sparse: indices come from files)
  std::vector<uint32_t> start;   ///< size light.size()+1: light[k]'s vertices are sample[start[k], start[k+1])
  std::vector<uint32_t> sample;  ///< sample indices, ascending within one light
  uint32_t lights() const { return uint32_t(light.size()); }
  /// The sample indices of the area vertices of SceneDesc light @p l (empty if it has none).
  std::span<const uint32_t> vertices(uint32_t l) const {
    const auto it = std::lower_bound(light.begin(), light.end(), l);
    if (it == light.end() || *it != l) return {};
    const size_t k = size_t(it - light.begin());
    return {sample.data() + start[k], sample.data() + start[k + 1]};
  }
  bool has(uint32_t l) const { return !vertices(l).empty(); }
};

LightVertices lightVertices(const std::vector<LightSample>& samples) {
  std::vector<std::pair<uint32_t, uint32_t>> byLight;  // (light, sample)
  for (uint32_t i = 0; i < samples.size(); ++i)
    if (samples[i].kind == LightSampleKind::AreaVertex) byLight.push_back({samples[i].light, i});
  std::sort(byLight.begin(), byLight.end());
  LightVertices lv;
  for (const auto& [l, i] : byLight) {
    if (lv.light.empty() || lv.light.back() != l) lv.light.push_back(l), lv.start.push_back(uint32_t(lv.sample.size()));
    lv.sample.push_back(i);
  }
  lv.start.push_back(uint32_t(lv.sample.size()));
  return lv;
}

/// Bitwise float equality (the expansion must reproduce the stored factor exactly).
bool same(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

/// One light's factors in one row, with their closed forms.
struct Member {
  uint64_t k;      ///< index of the factor in the table
  double scale, U;
};

/// The common V (as stored, f32) that reproduces every member's factor bit for bit, or 0 if none is
/// found. Tried: 1, then the fraction recovered from the member with the largest U and its two
/// float neighbours.
float commonVisible(const FirstShotTable& t, const std::vector<Member>& members, double area) {
  auto reproduces = [&](float v) {
    if (!(v > 0.0f) || v > 1.0f) return false;
    for (const Member& m : members)
      if (!same(analyticFactor(m.scale, double(v), m.U, area), t.factor[m.k])) return false;
    return true;
  };
  if (reproduces(1.0f)) return 1.0f;
  const Member& big = *std::max_element(members.begin(), members.end(), [](const Member& a, const Member& b) { return a.U < b.U; });
  const float v = float(double(t.factor[big.k]) * area / (big.scale * big.U));
  for (float c : {v, std::nextafter(v, 0.0f), std::nextafter(v, 2.0f)})
    if (reproduces(c)) return c;
  return 0.0f;
}

}  // namespace

Vec3d analyticEye(const LightSample& s, double eyeOffset) {
  // As placeWindow (preprocess/window.cpp) places the hemicube's or tetrahedron's eye: position + offset·n.
  const Vec3d position(s.position);
  return s.kind == LightSampleKind::AreaVertex ? position + eyeOffset * Vec3d(s.normal) : position;
}

double analyticScale(const LightSample& s) {
  switch (s.kind) {
    case LightSampleKind::Point: return 1.0 / (4.0 * kPi);
    case LightSampleKind::AreaVertex: return double(s.weight);
    default: return 0.0;
  }
}

double analyticIntegral(const LightSample& s, double eyeOffset, const Patch& p) {
  Vec3d poly[4];
  for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
  const Vec3d eye = analyticEye(s, eyeOffset);
  switch (s.kind) {
    case LightSampleKind::Point: return analytic::polygonSolidAngle(eye, poly, int(p.count));
    case LightSampleKind::AreaVertex: return analytic::polygonCosineSolidAngle(eye, Vec3d(s.normal), poly, int(p.count));
    default: return 0.0;
  }
}

float recoveredVisible(float r, const LightSample& s, double eyeOffset, const Patch& p) {
  if (s.kind != LightSampleKind::Point && s.kind != LightSampleKind::AreaVertex) return -1.0f;
  return recoveredVisible(r, analyticScale(s), analyticIntegral(s, eyeOffset, p), p.area);
}

GroupedFactors groupFactors(const FirstShotTable& t) {
  const uint32_t n = t.mesh.size();
  GroupedFactors g;
  g.rowCount.resize(n), g.singleCount.resize(n), g.groupCount.resize(n);
  const bool analytic = t.settings.estimator == "analytic";
  const LightVertices lv = lightVertices(t.samples);
  // Per row: which factors went into groups, and the groups.
  std::vector<uint8_t> grouped(t.factor.size(), 0);
  std::vector<std::vector<std::pair<uint32_t, float>>> groups(n);
  if (analytic && lv.lights() > 0)
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& range) {
      std::vector<uint32_t> done;
      std::vector<Member> members;
      for (uint32_t j = range.begin(); j != range.end(); ++j) {
        const Patch& p = t.mesh.patches[j];
        const uint64_t b = t.rowStart[j], e = t.rowStart[j + 1];
        const auto first = t.sampleIndex.begin() + int64_t(b), last = t.sampleIndex.begin() + int64_t(e);
        done.clear();
        for (uint64_t k = b; k < e; ++k) {
          const LightSample& s = t.samples[t.sampleIndex[k]];
          if (s.kind != LightSampleKind::AreaVertex || std::find(done.begin(), done.end(), s.light) != done.end()) continue;
          done.push_back(s.light);
          // The row must hold exactly the light's vertices that see the patch (U > 0).
          members.clear();
          bool ok = true;
          for (const uint32_t i : lv.vertices(s.light)) {
            const double U = analyticIntegral(t.samples[i], t.areaEyeOffset, p);
            if (!(U > 0)) continue;
            const auto it = std::lower_bound(first, last, i);
            ok = it != last && *it == i;
            if (!ok) break;
            members.push_back({uint64_t(it - t.sampleIndex.begin()), analyticScale(t.samples[i]), U});
          }
          size_t inRow = 0;
          for (uint64_t q = b; q < e; ++q)
            inRow += t.samples[t.sampleIndex[q]].kind == LightSampleKind::AreaVertex && t.samples[t.sampleIndex[q]].light == s.light;
          if (!ok || members.size() < 2 || members.size() != inRow) continue;
          const float v = commonVisible(t, members, p.area);
          if (v == 0.0f) continue;
          for (const Member& m : members) grouped[m.k] = 1;
          groups[j].push_back({s.light, v});
        }
        std::sort(groups[j].begin(), groups[j].end());
      }
    });
  for (uint32_t j = 0; j < n; ++j) {
    g.rowCount[j] = uint32_t(t.rowStart[j + 1] - t.rowStart[j]);
    const size_t before = g.singleSample.size();
    for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k)
      if (!grouped[k]) g.singleSample.push_back(t.sampleIndex[k]), g.singleFactor.push_back(t.factor[k]);
    g.singleCount[j] = uint32_t(g.singleSample.size() - before);
    g.groupCount[j] = uint32_t(groups[j].size());
    for (const auto& [light, v] : groups[j]) g.groupLight.push_back(light), g.groupVisible.push_back(v);
  }
  return g;
}

void expandFactors(const GroupedFactors& g, uint64_t nonZeros, FirstShotTable& t,
                   const std::function<void(const std::string&)>& fail) {
  const uint32_t n = t.mesh.size();
  const uint32_t ns = uint32_t(t.samples.size());
  // Offsets from the counts, each checked against its array.
  std::vector<uint64_t> singleStart(size_t(n) + 1, 0), groupStart(size_t(n) + 1, 0);
  t.rowStart.assign(size_t(n) + 1, 0);
  for (uint32_t j = 0; j < n; ++j) {
    t.rowStart[j + 1] = t.rowStart[j] + g.rowCount[j];
    singleStart[j + 1] = singleStart[j] + g.singleCount[j];
    groupStart[j + 1] = groupStart[j] + g.groupCount[j];
  }
  if (t.rowStart[n] != nonZeros) fail("row lengths do not add up to the factor count (corrupt file)");
  if (singleStart[n] != g.singleSample.size()) fail("single counts do not add up to the single entries (corrupt file)");
  if (groupStart[n] != g.groupLight.size()) fail("group counts do not add up to the groups (corrupt file)");
  for (size_t k = 0; k < g.singleSample.size(); ++k)
    if (g.singleSample[k] >= ns || !(g.singleFactor[k] >= 0) || !std::isfinite(g.singleFactor[k]))
      fail("factor " + std::to_string(k) + " is invalid (corrupt file)");
  const LightVertices lv = lightVertices(t.samples);
  if (!g.groupLight.empty() && t.settings.estimator != "analytic")
    fail("grouped factors in a table of the \"" + t.settings.estimator + "\" estimator (corrupt file)");
  for (size_t k = 0; k < g.groupLight.size(); ++k) {
    if (!lv.has(g.groupLight[k]))
      fail("group " + std::to_string(k) + ": light " + std::to_string(g.groupLight[k]) + " has no area-light vertices (corrupt file)");
    if (!(g.groupVisible[k] > 0.0f) || !(g.groupVisible[k] <= 1.0f))
      fail("group " + std::to_string(k) + ": visible fraction outside (0, 1] (corrupt file)");
  }
  // A row holds at most its singles and the vertices of its groups' lights (each light once, ascending):
  // a larger count is corrupt and must not size the arrays below.
  for (uint32_t j = 0; j < n; ++j) {
    uint64_t most = g.singleCount[j];
    for (uint64_t q = groupStart[j]; q < groupStart[j + 1]; ++q) {
      if (q > groupStart[j] && g.groupLight[q] <= g.groupLight[q - 1])
        fail("row " + std::to_string(j) + ": group lights not ascending or listed twice (corrupt file)");
      most += lv.vertices(g.groupLight[q]).size();
    }
    if (g.rowCount[j] > most)
      fail("row " + std::to_string(j) + ": its entries expand to at most " + std::to_string(most) + " factors, not " +
           std::to_string(g.rowCount[j]) + " (corrupt file)");
  }
  // Rows in parallel; the first bad row (lowest index) is reported.
  t.sampleIndex.resize(t.rowStart[n]);
  t.factor.resize(t.rowStart[n]);
  t.visible.resize(t.rowStart[n]);
  std::atomic<uint32_t> badRow{n};
  std::mutex badMutex;
  std::string badMessage;
  struct Entry {
    uint32_t sample;
    float factor, visible;
  };
  tbb::enumerable_thread_specific<std::vector<Entry>> buffers;
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& range) {
    auto& row = buffers.local();
    for (uint32_t j = range.begin(); j != range.end(); ++j) {
      auto bad = [&](const std::string& msg) {
        std::lock_guard lock(badMutex);
        if (j < badRow) badRow = j, badMessage = "row " + std::to_string(j) + ": " + msg + " (corrupt file)";
      };
      row.clear();
      const Patch& p = t.mesh.patches[j];
      for (uint64_t k = singleStart[j]; k < singleStart[j + 1]; ++k) {
        const float r = g.singleFactor[k];
        row.push_back({g.singleSample[k], r, recoveredVisible(r, t.samples[g.singleSample[k]], t.areaEyeOffset, p)});
      }
      if (groupStart[j] < groupStart[j + 1]) {
        for (uint64_t q = groupStart[j]; q < groupStart[j + 1]; ++q) {
          const uint32_t light = g.groupLight[q];
          const double v = double(g.groupVisible[q]);
          for (const uint32_t i : lv.vertices(light)) {
            const LightSample& s = t.samples[i];
            const double U = analyticIntegral(s, t.areaEyeOffset, p);
            if (!(U > 0)) continue;
            const double scale = analyticScale(s);
            const float r = analyticFactor(scale, v, U, p.area);
            row.push_back({i, r, recoveredVisible(r, scale, U, p.area)});
          }
        }
        std::sort(row.begin(), row.end(), [](const Entry& a, const Entry& b) { return a.sample < b.sample; });
      }
      if (row.size() != g.rowCount[j]) {
        bad("its entries expand to " + std::to_string(row.size()) + " factors, not " + std::to_string(g.rowCount[j]));
        continue;
      }
      const uint64_t b = t.rowStart[j];
      for (size_t k = 0; k < row.size(); ++k) {
        if (k > 0 && row[k].sample <= row[k - 1].sample) {
          bad("light samples not ascending or listed twice (sample " + std::to_string(row[k].sample) + ")");
          break;
        }
        if (!(row[k].factor >= 0) || !std::isfinite(row[k].factor)) {
          bad("a grouped factor is invalid");
          break;
        }
        t.sampleIndex[b + k] = row[k].sample, t.factor[b + k] = row[k].factor, t.visible[b + k] = row[k].visible;
      }
    }
  });
  if (badRow < n) fail(badMessage);
}

}  // namespace firstshot
