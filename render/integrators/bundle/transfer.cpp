// Ray-bundle stochastic iteration: one global transfer per iteration, deterministic for any thread count.
#include "render/integrators/bundle/transfer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <stdexcept>

#include "common/lights.h"
#include "common/rng.h"

namespace fs {

namespace {

/// Longest run of successive hits followed along one line (a guard against numerical loops).
constexpr int kMaxHitsPerLine = 1 << 16;

/// Side of a surface with front normal @p n that faces along @p w: 0 front, 1 back; −1 grazing.
int sideFacing(const Vec3& n, const Vec3& w) {
  const float c = glm::dot(n, w);
  return c > 0.0f ? 0 : c < 0.0f ? 1 : -1;
}

}  // namespace

void BundleTransfer::build(const RenderScene& scene, const BundleSettings& settings, Comm* comm) {
  scene_ = &scene;
  settings_ = settings;
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
  for (auto* v : {&incoming_, &point_, &prevIncoming_, &prevPoint_, &outgoing_}) v->assign(slots, Color(0.0f));
  dirIrradiance_.assign(directional_.size() * elements_.size(), Color(0.0f));
  dir_ = prevDir_ = Vec3(0.0f, 0.0f, 1.0f);
  done_ = rays_ = 0;
}

void BundleTransfer::iterate(uint64_t seed) {
  std::swap(prevIncoming_, incoming_);
  std::swap(prevPoint_, point_);
  prevDir_ = dir_;
  dir_ = bundleDirection(settings_.directions, seed, done_);
  rays_ = 0;
  traceDirectional(seed);
  computeOutgoing();
  traceBundle(seed);
  ++done_;
}

Color BundleTransfer::outgoingOf(uint32_t e, int side, const Vec3& w) const {
  const RenderScene& scene = *scene_;
  const BundleElement& el = elements_[e];
  const size_t slot = 2 * size_t(e) + side;
  Color L(0.0f);
  if (el.light != kNoId && side == 0) {
    const RenderLight& light = scene.lights().lights()[el.light];
    if (!light.replaced) L += light.radiance;  // a replaced light's first reflection is the first-shot term
  }
  const BSDF& bsdf = scene.bsdf(el.material);
  if (bsdf.hasDelta() || maxComponent(bsdf.albedo()) <= 0.0f) return L;
  const FirstShotTable* table = scene.firstShot();
  const bool firstShot = table && e < table->mesh.size();
  if (bsdf.isDiffuse()) {  // f = ρ/π for every direction on side s: the sum of irradiances, no frames
    Color E = (2.0f * kPiF) * (prevIncoming_[slot] + prevPoint_[slot]);
    if (firstShot) E += sideIrradiance_[slot];
    for (size_t d = 0; d < directional_.size(); ++d)
      if (sideFacing(el.normal, -scene.lights().lights()[directional_[d]].direction) == side) E += directionalIrradiance(d, e);
    return L + bsdf.albedo() * kInvPiF * E;
  }
  const Frame frame(el.normal);
  const Vec3 wo = frame.toLocal(w);
  // What the previous iteration brought, from ±ω_{k−1} on this side.
  const Color in = prevIncoming_[slot] + prevPoint_[slot];
  if (maxComponent(in) > 0.0f) {
    const bool onFront = glm::dot(el.normal, prevDir_) > 0.0f;
    const Vec3 wi = (onFront == (side == 0)) ? prevDir_ : -prevDir_;
    L += (2.0f * kPiF) * bsdf.eval(BSDFQuery(frame.toLocal(wi), wo)) * in;
  }
  // First-shot: the patch average per light sample, directions from the centroid.
  if (firstShot) {
    const Vec3 c = table->mesh.patches[e].centroid;
    for (uint64_t k = table->rowStart[e]; k < table->rowStart[e + 1]; ++k) {
      const LightSample& s = table->samples[table->sampleIndex[k]];
      const Vec3 wi = s.kind == LightSampleKind::Directional ? -s.normal : glm::normalize(s.position - c);
      L += s.emission * table->factor[k] * bsdf.eval(BSDFQuery(frame.toLocal(wi), wo));
    }
  }
  for (size_t d = 0; d < directional_.size(); ++d) {
    const Color& E = directionalIrradiance(d, e);
    if (maxComponent(E) > 0.0f) {
      const Vec3 wi = -scene.lights().lights()[directional_[d]].direction;
      L += bsdf.eval(BSDFQuery(frame.toLocal(wi), wo)) * E;
    }
  }
  return L;
}

void BundleTransfer::computeOutgoing() {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, elements_.size(), 1024), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t e = r.begin(); e < r.end(); ++e) {
      const Vec3& n = elements_[e].normal;
      const int front = sideFacing(n, dir_);  // the side ω_k leaves from
      for (int side = 0; side < 2; ++side)
        outgoing_[2 * size_t(e) + side] =
            front < 0 ? Color(0.0f) : outgoingOf(e, side, side == front ? dir_ : -dir_);
    }
  });
}

void BundleTransfer::traceDirectional(uint64_t seed) {
  const RenderScene& scene = *scene_;
  const int B = settings_.resolution;
  chunks_.resize(size_t(B));
  for (size_t d = 0; d < directional_.size(); ++d) {
    const RenderLight& light = scene.lights().lights()[directional_[d]];
    const Vec3 dir = glm::normalize(light.direction);
    const Vec2 offset(hashToUnit(seed, kBundleKey, done_, 2 + d, 0), hashToUnit(seed, kBundleKey, done_, 2 + d, 1));
    const BundleGrid grid(dir, elements_.center(), elements_.radius(), B, offset);
    std::atomic<uint64_t> rays{0};
    tbb::parallel_for(0, B, [&](int a) {
      enableFlushToZero();
      std::vector<Deposit>& out = chunks_[size_t(a)];
      out.clear();
      if (comm_ && !comm_->mine(uint64_t(a))) return;  // another rank's row
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
      rays += n;
    });
    rays_ += shareChunks(rays);
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
  chunks_.resize(size_t(B));
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(0, B, [&](int a) {
    enableFlushToZero();
    std::vector<Deposit>& out = chunks_[size_t(a)];
    out.clear();
    if (comm_ && !comm_->mine(uint64_t(a))) return;  // another rank's row
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
        const Color& forward = outgoing_[nearSlot];  // travels along +ω_k into far's side facing −ω_k
        const Color& backward = outgoing_[farSlot];  // travels along −ω_k into near's side facing +ω_k
        if (maxComponent(forward) > 0.0f) out.push_back({farSlot, forward});
        if (maxComponent(backward) > 0.0f) out.push_back({nearSlot, backward});
      }
    }
    rays += n;
  });
  rays_ += shareChunks(rays);

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
  gather(incoming_, grid.cellArea(), false);
  gather(point_, 1.0f, true);
}

uint64_t BundleTransfer::shareChunks(uint64_t rays) {
  if (!comm_) return rays;
  const auto start = std::chrono::steady_clock::now();
  // Per rank: its rays, then per row of its own, in order: the row and its deposits.
  ByteWriter out;
  out.put<uint64_t>(rays);
  for (size_t a = 0; a < chunks_.size(); ++a)
    if (comm_->mine(a)) {
      out.put<uint32_t>(uint32_t(a));
      out.putVector(chunks_[a]);
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
      if (a >= chunks_.size() || comm_->owner(a) != r)
        throw std::runtime_error("bundle transfer: exchange between ranks out of order");
      chunks_[a] = in.getVector<Deposit>();
    }
  }
  exchangeSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

void BundleTransfer::gather(std::vector<Color>& target, float scale, bool pointLines) {
  std::fill(target.begin(), target.end(), Color(0.0f));
  if (pointLines) {
    for (const Deposit& d : pointDeposits_) target[d.slot] += d.value;
  } else {
    for (const auto& chunk : chunks_)
      for (const Deposit& d : chunk) target[d.slot] += d.value;
  }
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, elements_.size(), 4096), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t e = r.begin(); e < r.end(); ++e) {
      const float a = elements_[e].area, f = a > 0.0f ? scale / a : 0.0f;
      target[2 * size_t(e)] *= f;
      target[2 * size_t(e) + 1] *= f;
    }
  });
}

}  // namespace fs
