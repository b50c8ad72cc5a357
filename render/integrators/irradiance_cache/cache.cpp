// Irradiance records, Ward's weights and the per-level octrees.
#include "render/integrators/irradiance_cache/cache.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

namespace {

constexpr int kMaxDepth = 24;  ///< octree depth limit (cube side / 2^24): records with tinier domains stay there

/// Octant of @p p in the cube at @p o with half side @p h: bit 0 = x, 1 = y, 2 = z upper half.
int octant(const Vec3& p, const Vec3& o, float h) {
  return (p.x >= o.x + h ? 1 : 0) | (p.y >= o.y + h ? 2 : 0) | (p.z >= o.z + h ? 4 : 0);
}

Vec3 octantOrigin(const Vec3& o, float h, int c) {
  return o + h * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
}

}  // namespace

float irradianceWeight(const Vec3& pi, const Vec3& ni, float Ri, const Vec3& p, const Vec3& n) {
  const float den = glm::length(p - pi) / Ri + std::sqrt(std::max(0.0f, 1.0f - glm::dot(n, ni)));
  return den > 0.0f ? 1.0f / den : std::numeric_limits<float>::infinity();
}

float inFrontDistance(const Vec3& pi, const Vec3& ni, const Vec3& p, const Vec3& n) {
  return glm::dot(p - pi, 0.5f * (n + ni));
}

Color extrapolateIrradiance(const IrradianceRecord& r, const Vec3& p, const Vec3& n) {
  // A domain widened by the footprint clamp (radius > R) would carry the gradient further than
  // the geometry warrants: scale it by R / radius (Křivánek et al.'s gradient limit).
  const float R = r.radius();
  const Vec3 dn = glm::cross(r.n, n), dp = (R > r.R ? r.R / R : 1.0f) * (p - r.p);
  Color e;
  for (int c = 0; c < 3; ++c) e[c] = std::max(0.0f, r.E[c] + glm::dot(dn, r.gradR[c]) + glm::dot(dp, r.gradT[c]));
  return e;
}

/// A published record. What a lookup reads of a rejected record (next, R, P_i, N_i, Rmin, Rmax)
/// lies in the first cache line.
struct alignas(64) IrradianceCache::Stored {
  Stored(const IrradianceRecord& r, int d) : R(r.R), depth(d), rec(r) {}
  const Stored* next = nullptr;  ///< next record of the same node (set before publication)
  mutable std::atomic<float> R;  ///< R_i; neighbour clamping only lowers it
  int depth = 0;
  IrradianceRecord rec;          ///< rec.R is the radius at insertion; the current one is R
};

struct IrradianceCache::Node {
  std::atomic<Node*> child[8] = {};
  std::atomic<const Stored*> head{nullptr};  ///< newest record of this node
};

/// A level's octree as freeze() copies it: nodes by index (the root first), each with its records' range; a record's
/// fields that a lookup tests side by side, in the order of the nodes' lists.
struct IrradianceCache::Frozen {
  struct FrozenNode {
    int32_t child[8];  ///< index of each octant's node, −1 for none
    uint32_t begin, end;  ///< its records
    /// The box around the valid domains a·R_i (relax 1) of the records of this node and those below it, a little
    /// wider than rounding could move them: a point outside it is accepted by none of them.
    Vec3 lo, hi;
  };
  struct Tested {
    Vec3 p;        ///< P_i
    float radius;  ///< clamp(R_i, Rmin, Rmax) at freeze()
    Vec3 n;        ///< N_i
    int32_t zone;
  };
  std::vector<FrozenNode> nodes;
  std::vector<Tested> tested;
  std::vector<const Stored*> stored;  ///< the record itself (its values and gradients), by the same index
};

struct IrradianceCache::Level {
  Node root;
  std::deque<Node> nodes;      ///< every other node (a deque keeps addresses stable)
  std::deque<Stored> records;  ///< in insertion order
  mutable std::mutex mutex;    ///< serialises inserts and whole-level reads
  Frozen frozen;               ///< freeze()'s copy, valid while isFrozen
  std::atomic<bool> isFrozen{false};
};

IrradianceCache::IrradianceCache(const Vec3& lo, const Vec3& hi, std::vector<float> accuracy)
    : accuracy_(std::move(accuracy)) {
  const Vec3 ext = hi - lo;
  const float side = std::max({ext.x, ext.y, ext.z, 1e-3f});
  size_ = side * 1.02f;  // a margin so that every surface point lies well inside
  origin_ = 0.5f * (lo + hi) - Vec3(0.5f * size_);
  frontTolerance_ = 1e-5f * size_;
  for (size_t i = 0; i < accuracy_.size(); ++i) levels_.push_back(std::make_unique<Level>());
}

IrradianceCache::~IrradianceCache() = default;

template <typename F>
void IrradianceCache::visit(const Level& level, const Vec3& p, float radius, float nodeReach, F&& f) const {
  struct Item {
    const Node* node;
    Vec3 o;
    float s;
  };
  Item stack[8 * (kMaxDepth + 2)];
  int top = 0;
  stack[top++] = {&level.root, origin_, size_};
  while (top > 0) {
    const Item it = stack[--top];
    for (const Stored* r = it.node->head.load(std::memory_order_acquire); r; r = r->next) f(*r);
    const float h = 0.5f * it.s;
    // §3.3: search a child if P is within half the child's size of its cube (nodeReach = 1/2).
    const float reach = std::max(radius, nodeReach * h);
    for (int c = 0; c < 8; ++c) {
      const Node* child = it.node->child[c].load(std::memory_order_acquire);
      if (!child) continue;
      const Vec3 o = octantOrigin(it.o, h, c);
      if (p.x < o.x - reach || p.x > o.x + h + reach || p.y < o.y - reach || p.y > o.y + h + reach ||
          p.z < o.z - reach || p.z > o.z + h + reach)
        continue;
      stack[top++] = {child, o, h};
    }
  }
}

template <typename F>
void IrradianceCache::visitFrozen(const Frozen& frozen, const Vec3& p, float nodeReach, bool prune, F&& f) const {
  struct Item {
    int32_t node;
    Vec3 o;
    float s;
  };
  Item stack[8 * (kMaxDepth + 2)];
  int top = 0;
  stack[top++] = {0, origin_, size_};
  while (top > 0) {
    const Item it = stack[--top];
    const Frozen::FrozenNode& node = frozen.nodes[size_t(it.node)];
    if (prune && (p.x < node.lo.x || p.y < node.lo.y || p.z < node.lo.z || p.x > node.hi.x || p.y > node.hi.y ||
                  p.z > node.hi.z))
      continue;  // none of its records' domains, nor those below it, holds p
    for (uint32_t i = node.begin; i < node.end; ++i) f(i);
    const float h = 0.5f * it.s, reach = nodeReach * h;  // visit()'s test, in the same order
    for (int c = 0; c < 8; ++c) {
      if (node.child[c] < 0) continue;
      const Vec3 o = octantOrigin(it.o, h, c);
      if (p.x < o.x - reach || p.x > o.x + h + reach || p.y < o.y - reach || p.y > o.y + h + reach ||
          p.z < o.z - reach || p.z > o.z + h + reach)
        continue;
      stack[top++] = {node.child[c], o, h};
    }
  }
}

void IrradianceCache::lookup(int level, const Vec3& p, const Vec3& n, bool gradients, IrradianceEstimate& est,
                             float relax, int32_t zone) const {
  relax = std::clamp(relax, 1.0f, 2.0f);  // a node of side s holds domains a·R_i < s/2
  const float a = relax * accuracy_[size_t(level)], invA = 1.0f / a;
  // R: the radius the weights use (the current R_i, clamped).
  auto test = [&](const Vec3& pi, const Vec3& ni, float R, int32_t zi, const Stored& s) {
    const Vec3 dp = p - pi;
    const float d2 = glm::dot(dp, dp), cosN = glm::dot(n, ni);
    if (!(d2 < (a * R) * (a * R)) || !(cosN > 0.0f)) return;  // w > 1/a needs |P − P_i| < a·R_i
    if (zi != zone) return;
    const float den = std::sqrt(d2) / R + std::sqrt(std::max(0.0f, 1.0f - cosN));
    const float w = 1.0f / std::max(den, 1e-6f);  // finite at P = P_i
    if (!(w > invA)) return;
    if (inFrontDistance(pi, ni, p, n) < -frontTolerance_) return;
    const IrradianceRecord& r = s.rec;
    est.sum += w * (gradients ? extrapolateIrradiance(r, p, n) : r.E);
    est.weight += w;
    ++est.count;
  };
  const Level& L = *levels_[size_t(level)];
  if (L.isFrozen.load(std::memory_order_acquire)) {
    const Frozen& f = L.frozen;
    visitFrozen(f, p, 0.5f * relax, relax == 1.0f, [&](uint32_t i) {
      const Frozen::Tested& t = f.tested[i];
      test(t.p, t.n, t.radius, t.zone, *f.stored[i]);
    });
    return;
  }
  visit(L, p, 0.0f, 0.5f * relax, [&](const Stored& s) {
    const IrradianceRecord& r = s.rec;
    test(r.p, r.n, std::min(std::max(s.R.load(std::memory_order_relaxed), r.Rmin), r.Rmax), r.zone, s);
  });
}

void IrradianceCache::freeze() {
  for (const std::unique_ptr<Level>& level : levels_) {
    Level& L = *level;
    std::lock_guard<std::mutex> lock(L.mutex);
    if (L.isFrozen.load(std::memory_order_relaxed)) continue;  // nothing inserted since its copy was made
    Frozen& f = L.frozen;
    f.nodes.clear(), f.tested.clear(), f.stored.clear();
    // Depth first, each node's records in its list's order (newest first), as visit() meets them.
    std::vector<std::pair<const Node*, int32_t>> todo{{&L.root, 0}};
    f.nodes.emplace_back();
    while (!todo.empty()) {
      const auto [node, index] = todo.back();
      todo.pop_back();
      Frozen::FrozenNode fn;
      fn.begin = uint32_t(f.tested.size());
      for (const Stored* r = node->head.load(std::memory_order_relaxed); r; r = r->next) {
        const IrradianceRecord& rec = r->rec;
        f.tested.push_back({rec.p, std::min(std::max(r->R.load(std::memory_order_relaxed), rec.Rmin), rec.Rmax),
                            rec.n, rec.zone});
        f.stored.push_back(r);
      }
      fn.end = uint32_t(f.tested.size());
      for (int c = 0; c < 8; ++c) {
        const Node* child = node->child[c].load(std::memory_order_relaxed);
        fn.child[c] = child ? int32_t(f.nodes.size()) : -1;
        if (child) {
          todo.emplace_back(child, fn.child[c]);
          f.nodes.emplace_back();
        }
      }
      f.nodes[size_t(index)] = fn;
    }
    // The domains' boxes, children before parents (a child's index is above its parent's).
    const float a = accuracy_[size_t(&level - levels_.data())], pad = 1e-5f * size_;
    for (size_t k = f.nodes.size(); k-- > 0;) {
      Frozen::FrozenNode& fn = f.nodes[k];
      fn.lo = Vec3(std::numeric_limits<float>::infinity()), fn.hi = -fn.lo;
      for (uint32_t i = fn.begin; i < fn.end; ++i) {
        const float r = a * f.tested[i].radius * 1.0001f + pad;
        fn.lo = glm::min(fn.lo, f.tested[i].p - Vec3(r)), fn.hi = glm::max(fn.hi, f.tested[i].p + Vec3(r));
      }
      for (int c = 0; c < 8; ++c)
        if (fn.child[c] >= 0)
          fn.lo = glm::min(fn.lo, f.nodes[size_t(fn.child[c])].lo), fn.hi = glm::max(fn.hi, f.nodes[size_t(fn.child[c])].hi);
    }
    L.isFrozen.store(true, std::memory_order_release);
  }
}

bool IrradianceCache::covers(int level, const Vec3& p, const Vec3& n, int32_t zone) const {
  IrradianceEstimate est;
  lookup(level, p, n, false, est, 1.0f, zone);
  return est.count > 0;
}

template <typename F>
void IrradianceCache::visitNeighbours(int level, const Vec3& p, float R, F&& f) const {
  // Records at a node of side s have 2·a·R_j < s, so nodes within their own side hold them all.
  const float twoA = 2.0f * accuracy_[size_t(level)];
  visit(*levels_[size_t(level)], p, std::isfinite(R) ? R : 0.0f, 1.0f, [&](const Stored& s) {
    const float d = glm::length(p - s.rec.p), Rj = s.R.load(std::memory_order_relaxed);
    if (d < R || d < twoA * Rj) f(s, d, Rj);
  });
}

void IrradianceCache::clampToNeighbours(int level, IrradianceRecord& r) const {
  visitNeighbours(level, r.p, r.R, [&](const Stored&, float d, float Rj) { r.R = std::min(r.R, Rj + d); });
}

void IrradianceCache::insert(int level, IrradianceRecord r, bool neighbourClamp, bool shrinkNeighbours) {
  Level& L = *levels_[size_t(level)];
  std::lock_guard<std::mutex> lock(L.mutex);
  L.isFrozen.store(false, std::memory_order_relaxed);  // the copy is stale from here (freeze() makes another)
  if (neighbourClamp) {
    clampToNeighbours(level, r);
    // Shrink the neighbours, and theirs in turn while radii drop (a distance transform over the
    // neighbour graph). The mutex is held: no other writer.
    std::vector<std::pair<Vec3, float>> work;
    if (shrinkNeighbours) work.emplace_back(r.p, r.R);
    for (size_t w = 0; w < work.size() && w < 4096; ++w) {
      const Vec3 p = work[w].first;
      const float R = work[w].second;  // not a structured binding: clang 14 cannot capture those
      visitNeighbours(level, p, R, [&](const Stored& s, float d, float Rj) {
        if (Rj > R + d * 1.0001f) {
          s.R.store(R + d, std::memory_order_relaxed);
          work.emplace_back(s.rec.p, R + d);
        }
      });
    }
  }
  // Descend while the child would still be larger than twice the valid domain a·R_i.
  const float domain = accuracy_[size_t(level)] * r.radius();
  Node* node = &L.root;
  Vec3 o = origin_;
  float s = size_;
  int depth = 0;
  while (depth < kMaxDepth && 0.5f * s > 2.0f * domain) {
    const float h = 0.5f * s;
    const int c = octant(r.p, o, h);
    Node* child = node->child[c].load(std::memory_order_relaxed);
    if (!child) {
      child = &L.nodes.emplace_back();
      node->child[c].store(child, std::memory_order_release);
    }
    node = child;
    o = octantOrigin(o, h, c);
    s = h;
    ++depth;
  }
  Stored& st = L.records.emplace_back(r, depth);
  st.next = node->head.load(std::memory_order_relaxed);
  node->head.store(&st, std::memory_order_release);
}

size_t IrradianceCache::size(int level) const {
  const Level& L = *levels_[size_t(level)];
  std::lock_guard<std::mutex> lock(L.mutex);
  return L.records.size();
}

size_t IrradianceCache::size() const {
  size_t n = 0;
  for (int l = 0; l < levels(); ++l) n += size(l);
  return n;
}

std::vector<IrradianceRecord> IrradianceCache::records(int level) const {
  const Level& L = *levels_[size_t(level)];
  std::lock_guard<std::mutex> lock(L.mutex);
  std::vector<IrradianceRecord> out;
  out.reserve(L.records.size());
  for (const Stored& s : L.records) {
    out.push_back(s.rec);
    out.back().R = s.R.load(std::memory_order_relaxed);
  }
  return out;
}

std::vector<int> IrradianceCache::nodeDepths(int level) const {
  const Level& L = *levels_[size_t(level)];
  std::lock_guard<std::mutex> lock(L.mutex);
  std::vector<int> out;
  for (const Stored& s : L.records) out.push_back(s.depth);
  return out;
}

}  // namespace firstshot
