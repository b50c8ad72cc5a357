// Ray-bundle stochastic iteration: one global transfer per iteration, deterministic for any thread count.
#include "render/integrators/bundle/transfer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <stdexcept>

#include "common/lights/spot_cone.h"
#include "common/sampling/rng.h"
#include "render/firstshot/reflected.h"
#include "render/scene/table_rows.h"

namespace firstshot {

namespace {

/// Longest run of successive hits followed along one line (a guard against numerical loops).
constexpr int kMaxHitsPerLine = 1 << 16;

/// Side of a surface with front normal @p n that faces along @p w: 0 front, 1 back; −1 grazing.
int sideFacing(const Vec3& n, const Vec3& w) {
  const float c = glm::dot(n, w);
  return c > 0.0f ? 0 : c < 0.0f ? 1 : -1;
}

}  // namespace

void BundleTransfer::build(const RenderScene& scene, const BundleSettings& settings, Comm* comm, int maxDepth) {
  scene_ = &scene;
  settings_ = settings;
  lumped_ = maxDepth > kMaxOrders;
  orders_ = lumped_ ? 1 : std::max(1, maxDepth);  // depth 0 reflects nothing: order 0 is kept, never read
  comm_ = comm && comm->size() > 1 ? comm : nullptr;
  exchangeBytes_ = 0;
  exchangeSeconds_ = 0;
  elements_.build(scene);
  sideIrradiance_ = scene.firstShot() ? scene.firstShot()->sideIrradiance() : std::vector<Color>();
  points_.clear();
  directional_.clear();
  const auto& lights = scene.lights().lights();
  for (uint32_t l = 0; l < lights.size(); ++l) {
    if (lights[l].replaced) continue;
    if (lights[l].type == LightType::Point || lights[l].type == LightType::Spot) points_.push_back(l);
    if (lights[l].type == LightType::Directional) directional_.push_back(l);
  }
  reset();
}

void BundleTransfer::reset() {
  const size_t slots = 2 * size_t(elements_.size());
  for (auto* v : {&incoming_, &outgoing_}) v->assign(slots * size_t(orders_), Color(0.0f));
  for (auto* v : {&outgoingTotal_, &point_, &prevPoint_}) v->assign(slots, Color(0.0f));
  dirIrradiance_.assign(directional_.size() * elements_.size(), Color(0.0f));
  dir_ = prevDir_ = Vec3(0.0f, 0.0f, 1.0f);
  done_ = rays_ = 0;
}

void BundleTransfer::iterate(uint64_t seed) {
  std::swap(prevPoint_, point_);  // incoming_ stays the previous iteration's until the links are summed
  prevDir_ = dir_;
  dir_ = bundleDirection(settings_.directions, seed, done_);
  rays_ = 0;
  traceDirectional(seed);
  computeOutgoing();
  traceBundle(seed);
  ++done_;
}

void BundleTransfer::outgoingOf(uint32_t e, int side, const Vec3& w, Color* out) const {
  // Order 0 is the emission; the direct terms (first-shot, directional, the point lights' P) and the
  // reflection of I^(0) are order 1, the reflection of I^(b−1) order b. Lumped: all in out[0].
  const RenderScene& scene = *scene_;
  const BundleElement& el = elements_[e];
  const size_t slot = 2 * size_t(e) + side;
  const Color* prev = &incoming_[slot * size_t(orders_)];  // I^(b) of the previous iteration
  const int direct = lumped_ ? 0 : 1;                      // where order-1 light goes (none if orders_ == 1)
  for (int b = 0; b < orders_; ++b) out[b] = Color(0.0f);
  if (el.light != kNoId && side == 0) {
    const RenderLight& light = scene.lights().lights()[el.light];
    if (!light.replaced) out[0] += light.radiance;  // a replaced light's first reflection is the first-shot term
  }
  const BSDF& bsdf = e < scene.mesh().size() ? scene.patchBsdf(e) : scene.bsdf(el.material);  // patches first
  if (bsdf.hasDelta() || maxComponent(bsdf.albedo()) <= 0.0f || direct >= orders_) return;
  const FirstShotTable* table = scene.firstShot();
  const bool firstShot = table && e < table->mesh.size();
  if (bsdf.isDiffuse()) {  // f = ρ/π for every direction on side s: the sum of irradiances, no frames
    const Color rho = bsdf.albedo() * kInvPiF;
    Color E = (2.0f * kPiF) * (prev[0] + prevPoint_[slot]);
    if (firstShot) E += sideIrradiance_[slot];
    for (size_t d = 0; d < directional_.size(); ++d)
      if (sideFacing(el.normal, -scene.lights().lights()[directional_[d]].direction) == side) E += directionalIrradiance(d, e);
    out[direct] += rho * E;
    for (int b = 2; b < orders_; ++b) out[b] = rho * ((2.0f * kPiF) * prev[b - 1]);
    return;
  }
  const Frame frame(el.normal);
  const Vec3 wo = frame.toLocal(w);
  // What the previous iteration brought, from ±ω_{k−1} on this side.
  Color in(0.0f);
  for (int b = 0; b < orders_; ++b) in += prev[b];
  in += prevPoint_[slot];
  if (maxComponent(in) > 0.0f) {
    const bool onFront = glm::dot(el.normal, prevDir_) > 0.0f;
    const Vec3 wi = (onFront == (side == 0)) ? prevDir_ : -prevDir_;
    const Color r = (2.0f * kPiF) * bsdf.eval(BSDFQuery(frame.toLocal(wi), wo));
    out[direct] += r * (prev[0] + prevPoint_[slot]);
    for (int b = 2; b < orders_; ++b) out[b] = r * prev[b - 1];
  }
  // First-shot: the patch average per light sample, directions from the centroid.
  if (firstShot) {
    auto patchAverage = [](const TableFactor&, const LightSample&, Vec3&, float&) { return true; };  // w_i = r_ij
    out[direct] = sumReflectedFirstShot(table->samples, TableRows(*table)[e], table->mesh.patches[e].centroid, frame,
                                        wo, bsdf, FirstShotProduct::EmissionFirst, out[direct], patchAverage);
  }
  for (size_t d = 0; d < directional_.size(); ++d) {
    const Color& E = directionalIrradiance(d, e);
    if (maxComponent(E) > 0.0f) {
      const Vec3 wi = -scene.lights().lights()[directional_[d]].direction;
      out[direct] += bsdf.eval(BSDFQuery(frame.toLocal(wi), wo)) * E;
    }
  }
}

void BundleTransfer::computeOutgoing() {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, elements_.size(), 1024), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t e = r.begin(); e < r.end(); ++e) {
      const Vec3& n = elements_[e].normal;
      const int front = sideFacing(n, dir_);  // the side ω_k leaves from
      for (int side = 0; side < 2; ++side) {
        const size_t slot = 2 * size_t(e) + side;
        Color* out = &outgoing_[slot * size_t(orders_)];
        if (front < 0) {
          for (int b = 0; b < orders_; ++b) out[b] = Color(0.0f);
        } else {
          outgoingOf(e, side, side == front ? dir_ : -dir_, out);
        }
        Color total(0.0f);
        for (int b = 0; b < orders_; ++b) total += out[b];
        outgoingTotal_[slot] = total;
      }
    }
  });
}

template <typename T, typename Row>
uint64_t BundleTransfer::traceRows(int rows, std::vector<std::vector<T>>& out, const Row& row) {
  out.resize(size_t(rows));
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(0, rows, [&](int a) {
    enableFlushToZero();
    out[size_t(a)].clear();
    if (comm_ && !comm_->mine(uint64_t(a))) return;  // another rank's row
    rays += row(a, out[size_t(a)]);
  });
  return shareChunks(out, rays);
}

void BundleTransfer::traceDirectional(uint64_t seed) {
  const RenderScene& scene = *scene_;
  const int B = settings_.resolution;
  for (size_t d = 0; d < directional_.size(); ++d) {
    const RenderLight& light = scene.lights().lights()[directional_[d]];
    const Vec3 dir = glm::normalize(light.direction);
    const Vec2 offset(hashToUnit(seed, kBundleKey, done_, 2 + d, 0), hashToUnit(seed, kBundleKey, done_, 2 + d, 1));
    const BundleGrid grid(dir, elements_.center(), elements_.radius(), B, offset);
    rays_ += traceRows(B, chunks_, [&](int a, std::vector<Deposit>& out) {
      uint64_t n = 0;
      Ray ray;
      Hit hit;
      for (int b = 0; b < B; ++b) {
        if (!grid.line(a, b, ray)) continue;
        ++n;
        if (!scene.intersect(ray, hit)) continue;
        const uint32_t e = elements_.index(hit);
        if (sideFacing(elements_[e].normal, dir) >= 0) out.push_back({e, light.irradiance});  // f_r(−d, w) picks the lit side
      }
      return n;
    });
    Color* D = &dirIrradiance_[d * elements_.size()];
    std::fill(D, D + elements_.size(), Color(0.0f));
    for (const auto& chunk : chunks_)
      for (const Deposit& dep : chunk) D[dep.slot] += dep.value;
    for (uint32_t e = 0; e < elements_.size(); ++e)
      D[e] *= elements_[e].area > 0.0f ? grid.cellArea() / elements_[e].area : 0.0f;
  }
}

void BundleTransfer::traceBundle(uint64_t seed) {
  const RenderScene& scene = *scene_;
  const int B = settings_.resolution;
  const Vec2 offset(hashToUnit(seed, kBundleKey, done_, 1, 0), hashToUnit(seed, kBundleKey, done_, 1, 1));
  const BundleGrid grid(dir_, elements_.center(), elements_.radius(), B, offset);
  rays_ += traceRows(B, links_, [&](int a, std::vector<Link>& out) {
    struct Crossing {
      uint32_t e;
      int side;  ///< the side facing +ω_k
    };
    std::vector<Crossing> along;
    std::vector<Hit> hits;
    uint64_t n = 0;
    Ray ray;
    Hit hit;
    auto cross = [&](const Hit& h) {
      const uint32_t e = elements_.index(h);
      const int side = sideFacing(elements_[e].normal, dir_);
      if (side >= 0 && (along.empty() || along.back().e != e)) along.push_back({e, side});
    };
    for (int b = 0; b < B; ++b) {
      if (!grid.line(a, b, ray)) continue;
      along.clear();
      if (settings_.allHits) {
        ++n;
        hits.clear();
        scene.embree().allHits(ray, hits);
        for (const Hit& h : hits) cross(h);
      } else {
        for (int i = 0; i < kMaxHitsPerLine; ++i) {  // successive closest hits
          ++n;
          if (!scene.intersect(ray, hit)) break;
          cross(hit);
          ray.tmin = hit.t + hit.eps;
        }
      }
      for (size_t i = 0; i + 1 < along.size(); ++i) {
        const Crossing near = along[i], far = along[i + 1];
        const uint32_t nearSlot = 2 * near.e + uint32_t(near.side), farSlot = 2 * far.e + uint32_t(1 - far.side);
        // near's outgoing travels along +ω_k into far's side facing −ω_k, far's along −ω_k into near's.
        if (maxComponent(outgoingTotal_[nearSlot]) > 0.0f) out.push_back({farSlot, nearSlot});
        if (maxComponent(outgoingTotal_[farSlot]) > 0.0f) out.push_back({nearSlot, farSlot});
      }
    }
    return n;
  });

  // The kept point and spot lights: one line each way along ±ω_k from the light.
  pointDeposits_.clear();
  for (uint32_t l : points_) {
    const RenderLight& light = scene.lights().lights()[l];
    for (const Vec3& w : {dir_, -dir_}) {
      Hit hit;
      ++rays_;
      if (!scene.intersect(Ray(light.position, w), hit)) continue;
      const uint32_t e = elements_.index(hit);
      const int side = sideFacing(elements_[e].normal, w);  // light arrives on the other side, facing −w
      if (side < 0) continue;
      Color I = light.intensity;
      if (light.type == LightType::Spot) I *= light.profile(w);
      if (maxComponent(I) > 0.0f) pointDeposits_.push_back({2 * e + uint32_t(1 - side), I});
    }
  }
  gatherLinks(grid.cellArea());
  gatherPoints();
}

template <typename T>
uint64_t BundleTransfer::shareChunks(std::vector<std::vector<T>>& chunks, uint64_t rays) {
  if (!comm_) return rays;
  const auto start = std::chrono::steady_clock::now();
  // Per rank: its rays, then per row of its own, in order: the row and its deposits.
  ByteWriter out;
  out.put<uint64_t>(rays);
  for (size_t a = 0; a < chunks.size(); ++a)
    if (comm_->mine(a)) {
      out.put<uint32_t>(uint32_t(a));
      out.putVector(chunks[a]);
    }
  const uint64_t before = comm_->bytesSent();
  const std::vector<Bytes> all = comm_->allGather(out.bytes());
  exchangeBytes_ += comm_->bytesSent() - before;
  uint64_t total = 0;
  for (int r = 0; r < comm_->size(); ++r) {
    ByteReader in(all[size_t(r)]);
    total += in.get<uint64_t>();
    if (r == comm_->rank()) continue;
    while (!in.done()) {
      const uint32_t a = in.get<uint32_t>();
      if (a >= chunks.size() || comm_->owner(a) != r)
        throw std::runtime_error("bundle transfer: exchange between ranks out of order");
      chunks[a] = in.getVector<T>();
    }
  }
  exchangeSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

void BundleTransfer::gatherPoints() {
  std::fill(point_.begin(), point_.end(), Color(0.0f));
  for (const Deposit& d : pointDeposits_) point_[d.slot] += d.value;
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, elements_.size(), 4096), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t e = r.begin(); e < r.end(); ++e) {
      const float a = elements_[e].area, f = a > 0.0f ? 1.0f / a : 0.0f;
      point_[2 * size_t(e)] *= f;
      point_[2 * size_t(e) + 1] *= f;
    }
  });
}

void BundleTransfer::gatherLinks(float scale) {
  // In row order, every order of a link at once: the same sums for any number of threads or ranks.
  const size_t O = size_t(orders_);
  std::fill(incoming_.begin(), incoming_.end(), Color(0.0f));
  for (const auto& chunk : links_)
    for (const Link& l : chunk) {
      Color* to = &incoming_[size_t(l.target) * O];
      const Color* from = &outgoing_[size_t(l.source) * O];
      for (size_t b = 0; b < O; ++b) to[b] += from[b];
    }
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, elements_.size(), 4096), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t e = r.begin(); e < r.end(); ++e) {
      const float a = elements_[e].area, f = a > 0.0f ? scale / a : 0.0f;
      for (size_t k = 2 * size_t(e) * O; k < (2 * size_t(e) + 2) * O; ++k) incoming_[k] *= f;
    }
  });
}

}  // namespace firstshot
