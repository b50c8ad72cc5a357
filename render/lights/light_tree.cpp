// Light tree: construction by the surface-area-orientation heuristic, sampling and pmf.
#include "render/lights/light_tree.h"

#include <algorithm>
#include <array>
#include <limits>

namespace firstshot {

namespace {

constexpr int kBuckets = 12;
constexpr int kBalancedFrom = 30;  ///< depth from which nodes split at the median: trails stay within 64 bits

float sizeMeasure(const LightBounds& b) {
  const Vec3 d = b.hi - b.lo;
  const float area = 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  return area > 0.0f ? area : glm::dot(d, d);  // points and segments: their spread
}

float cost(const LightBounds& b) { return b.phi * orientationMeasure(b) * sizeMeasure(b); }

}  // namespace

LightTree::LightTree(const std::vector<LightBounds>& emitters, const std::vector<uint32_t>* groupable, int maxLeaf) {
  trail_.assign(emitters.size(), 0);
  trailDepth_.assign(emitters.size(), 255);
  inLeaf_.assign(emitters.size(), 0.0f);
  power_.resize(emitters.size());
  for (size_t k = 0; k < emitters.size(); ++k) power_[k] = emitters[k].phi;
  std::vector<Item> items;
  items.reserve(emitters.size());
  for (uint32_t k = 0; k < emitters.size(); ++k)
    if (emitters[k].phi > 0.0f) items.push_back({emitters[k], emitters[k].centre(), k});
  if (items.empty()) return;
  groupable_ = groupable;
  maxLeaf_ = std::clamp(maxLeaf, 1, 64);
  nodes_.reserve(2 * items.size());
  build(items, 0, items.size(), 0, 0);
  groupable_ = nullptr;
}

float LightTree::Node::importance(const Vec3& p, const Vec3& n) const {
  return boundImportance(c, r2, w, phi, cosO, sinO, cosE, twoSided, p, n);
}

uint32_t LightTree::build(std::vector<Item>& items, size_t begin, size_t end, uint64_t trail, int depth) {
  const uint32_t self = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_[self].depth = static_cast<uint8_t>(depth);
  nodes_[self].first = static_cast<uint32_t>(leaf_.size());
  LightBounds all = items[begin].bounds;
  for (size_t i = begin + 1; i < end; ++i) all = unite(all, items[i].bounds);
  {
    Node& node = nodes_[self];
    const Vec3 diag = all.hi - all.lo;
    node.c = all.centre();
    node.r2 = 0.25f * glm::dot(diag, diag);
    node.w = all.w;
    node.phi = all.phi;
    node.cosO = all.cosO;
    node.sinO = std::sqrt(std::max(0.0f, 1.0f - all.cosO * all.cosO));
    node.cosE = all.cosE;
    node.twoSided = all.twoSided;
  }
  bool leaf = end - begin == 1;
  if (!leaf && groupable_ && end - begin <= size_t(maxLeaf_)) {
    leaf = true;
    const uint32_t group = (*groupable_)[items[begin].index];
    for (size_t i = begin; i < end && leaf; ++i) leaf = group != 0 && (*groupable_)[items[i].index] == group;
  }
  if (leaf) {
    Node& node = nodes_[self];
    node.child = static_cast<uint32_t>(leaf_.size());
    node.count = static_cast<uint16_t>(end - begin);
    // Not a Distribution1Df (common/sampling/distribution_1d.h): the leaves' CDFs share one array, searched linearly in the
    // hot path, and round as float(sum / total) with a rest of 0 in an empty interval, which the choices keep.
    double sum = 0, total = 0;
    for (size_t i = begin; i < end; ++i) total += items[i].bounds.phi;
    for (size_t i = begin; i < end; ++i) {
      const uint32_t e = items[i].index;
      sum += items[i].bounds.phi;
      leaf_.push_back(e);
      leafCdf_.push_back(i + 1 == end ? 1.0f : float(sum / total));
      inLeaf_[e] = float(items[i].bounds.phi / total);
      trail_[e] = trail;
      trailDepth_[e] = static_cast<uint8_t>(depth);
    }
    depth_ = std::max(depth_, depth);
    node.end = static_cast<uint32_t>(leaf_.size());
    return self;
  }
  Vec3 clo = items[begin].centroid, chi = clo;
  for (size_t i = begin + 1; i < end; ++i) {
    clo = glm::min(clo, items[i].centroid);
    chi = glm::max(chi, items[i].centroid);
  }

  // The split: the cheapest bucket boundary over the three axes (regularised towards cubic
  // nodes as pbrt does), or the median of the longest axis when costs say nothing.
  const Vec3 extent = chi - clo;
  const float maxExtent = std::max({extent.x, extent.y, extent.z});
  int bestAxis = -1, bestBucket = -1;
  float bestCost = std::numeric_limits<float>::infinity();
  if (depth < kBalancedFrom && maxExtent > 0.0f) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0f)) continue;
      std::array<LightBounds, kBuckets> bucket{};
      std::array<bool, kBuckets> used{};
      for (size_t i = begin; i < end; ++i) {
        const int b = std::min(kBuckets - 1, int(kBuckets * (items[i].centroid[axis] - clo[axis]) / extent[axis]));
        bucket[b] = used[b] ? unite(bucket[b], items[i].bounds) : items[i].bounds;
        used[b] = true;
      }
      const float regular = maxExtent / extent[axis];
      for (int s = 0; s < kBuckets - 1; ++s) {
        LightBounds below{}, above{};
        bool hasBelow = false, hasAbove = false;
        for (int b = 0; b <= s; ++b)
          if (used[b]) below = hasBelow ? unite(below, bucket[b]) : bucket[b], hasBelow = true;
        for (int b = s + 1; b < kBuckets; ++b)
          if (used[b]) above = hasAbove ? unite(above, bucket[b]) : bucket[b], hasAbove = true;
        if (!hasBelow || !hasAbove) continue;
        const float c = regular * (cost(below) + cost(above));
        if (c < bestCost) bestCost = c, bestAxis = axis, bestBucket = s;
      }
    }
  }
  size_t mid;
  if (bestAxis >= 0) {
    const float lo = clo[bestAxis], ext = extent[bestAxis];
    auto it = std::partition(items.begin() + long(begin), items.begin() + long(end), [&](const Item& item) {
      return std::min(kBuckets - 1, int(kBuckets * (item.centroid[bestAxis] - lo) / ext)) <= bestBucket;
    });
    mid = size_t(it - items.begin());
  } else {
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + long(begin), items.begin() + long(mid), items.begin() + long(end),
                     [axis](const Item& a, const Item& b) {
                       return a.centroid[axis] < b.centroid[axis] || (a.centroid[axis] == b.centroid[axis] && a.index < b.index);
                     });
  }
  if (mid == begin || mid == end) mid = begin + (end - begin) / 2;

  build(items, begin, mid, trail, depth + 1);
  const uint32_t second = build(items, mid, end, trail | (uint64_t(1) << depth), depth + 1);
  nodes_[self].child = second;
  nodes_[self].end = static_cast<uint32_t>(leaf_.size());
  return self;
}

bool LightTree::firstChildProbability(uint32_t node, const Vec3& p, const Vec3& n, const float* vis, float& p0) const {
  const Node& a = nodes_[node + 1];
  const Node& b = nodes_[nodes_[node].child];
  float i0 = a.importance(p, n), i1 = b.importance(p, n);
  if (vis) {
    if (a.top >= 0) i0 *= vis[a.top];
    if (b.top >= 0) i1 *= vis[b.top];
  }
  if (!(i0 + i1 > 0.0f)) return false;
  p0 = i0 / (i0 + i1);
  return true;
}

const float* LightTree::visibilityRow(const Vec3& p) const {
  if (!grid_ || topCount_ == 0) return nullptr;
  const int32_t r = grid_->rowOf(p);
  return r < 0 ? nullptr : visibility_.data() + size_t(r) * topCount_;
}

std::vector<uint32_t> LightTree::cut(int D) const {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].depth == D || (nodes_[i].depth < D && nodes_[i].count > 0)) out.push_back(i);
  return out;
}

void LightTree::emittersUnder(uint32_t node, std::vector<uint32_t>& emitters, std::vector<float>& power) const {
  emitters.assign(leaf_.begin() + nodes_[node].first, leaf_.begin() + nodes_[node].end);
  power.clear();
  for (uint32_t e : emitters) power.push_back(power_[e]);
}

void LightTree::setVisibility(std::shared_ptr<const VisibilityGrid> grid, int D, const std::vector<float>& cutVisibility,
                              float epsilon) {
  grid_ = std::move(grid);
  const std::vector<uint32_t> cutNodes = cut(D);
  topCount_ = 0;
  for (Node& node : nodes_) node.top = node.depth <= D ? int32_t(topCount_++) : -1;
  const size_t rows = grid_ ? grid_->rows : 0;
  visibility_.assign(rows * topCount_, 0.0f);
  std::vector<float> v(nodes_.size());
  for (size_t r = 0; r < rows; ++r) {
    for (size_t k = 0; k < cutNodes.size(); ++k) v[cutNodes[k]] = cutVisibility[r * cutNodes.size() + k];
    // Above the cut: power-weighted means, children before parents (they follow them in the array).
    for (size_t i = nodes_.size(); i-- > 0;) {
      const Node& node = nodes_[i];
      if (node.top < 0 || node.count > 0 || node.depth >= D) continue;
      const Node &a = nodes_[i + 1], &b = nodes_[node.child];
      v[i] = (a.phi * v[i + 1] + b.phi * v[node.child]) / std::max(a.phi + b.phi, 1e-30f);
    }
    for (size_t i = 0; i < nodes_.size(); ++i)
      if (nodes_[i].top >= 0) visibility_[r * topCount_ + size_t(nodes_[i].top)] = epsilon + (1.0f - epsilon) * v[i];
  }
}

uint32_t LightTree::descend(const Vec3& p, const Vec3& n, float& u, float& pmf) const {
  pmf = 1.0f;
  uint32_t node = 0;
  if (nodes_[0].count > 0) return 0;  // a single leaf: chosen within it by power alone
  const float* vis = visibilityRow(p);
  while (nodes_[node].count == 0) {
    float p0;
    if (!firstChildProbability(node, p, n, vis, p0)) {
      pmf = 0.0f;
      return node;
    }
    if (u < p0) {
      u = std::min(u / p0, 0x1.fffffep-1f);
      pmf *= p0;
      node = node + 1;
    } else {
      u = std::min((u - p0) / (1.0f - p0), 0x1.fffffep-1f);
      pmf *= 1.0f - p0;
      node = nodes_[node].child;
    }
  }
  return node;
}

bool LightTree::sample(const Vec3& p, const Vec3& n, float u, uint32_t& index, float& pmf, float* rest) const {
  if (nodes_.empty()) return false;
  const Node& leaf = nodes_[descend(p, n, u, pmf)];
  if (!(pmf > 0.0f)) return false;
  uint32_t k = 0;  // the emitter within the leaf, by power
  while (k + 1 < leaf.count && leafCdf_[leaf.child + k] <= u) ++k;
  index = leaf_[leaf.child + k];
  pmf *= inLeaf_[index];
  if (rest) {  // u's position within the chosen emitter's interval of the leaf's CDF
    const float lo = k > 0 ? leafCdf_[leaf.child + k - 1] : 0.0f;
    const float hi = k + 1 < leaf.count ? leafCdf_[leaf.child + k] : 1.0f;
    *rest = hi > lo ? std::clamp((u - lo) / (hi - lo), 0.0f, 0x1.fffffep-1f) : 0.0f;
  }
  return pmf > 0.0f;
}

float LightTree::pmf(const Vec3& p, const Vec3& n, uint32_t index) const {
  if (index >= trailDepth_.size() || trailDepth_[index] == 255) return 0.0f;
  float pmf = 1.0f;
  if (nodes_[0].count > 0) return inLeaf_[index];  // as descend(): no importance for a single leaf
  const uint64_t trail = trail_[index];
  const float* vis = visibilityRow(p);
  uint32_t node = 0;
  for (int d = 0; nodes_[node].count == 0; ++d) {
    float p0;
    if (!firstChildProbability(node, p, n, vis, p0)) return 0.0f;
    if ((trail >> d) & 1u) {
      pmf *= 1.0f - p0;
      node = nodes_[node].child;
    } else {
      pmf *= p0;
      node = node + 1;
    }
  }
  return pmf * inLeaf_[index];
}

}  // namespace firstshot
