// The table's luminaires seen by the renderer (luminaires.h).
#include "render/scene/luminaire_boxes.h"

#include <algorithm>
#include <cmath>

#include "render/scene/light_set.h"

namespace firstshot {

LuminaireBoxes::LuminaireBoxes(const std::vector<Luminaire>* luminaires, const LightSet& lights)
    : items_(luminaires) {
  if (empty()) return;
  for (const Luminaire& lum : *items_) anyDirect_ = anyDirect_ || maxComponent(lum.directPower) > 0.0f;
  lightLuminaire_.assign(lights.lights().size(), -1);
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const uint32_t s = lights.lights()[l].sceneIndex;
    for (size_t i = 0; i < items_->size(); ++i) {
      const std::vector<uint32_t>& ls = (*items_)[i].lights;
      if (std::binary_search(ls.begin(), ls.end(), s)) lightLuminaire_[l] = int(i);
    }
  }
  exitFirst_.assign(items_->size() + 1, 0);
  for (size_t i = 0; i < items_->size(); ++i) exitFirst_[i + 1] = exitFirst_[i] + (*items_)[i].patchCount();
  // Not a Distribution1Df per face (common/sampling/distribution_1d.h): the faces' CDFs share one array and keep their last
  // entry as rounded (not 1), which the last patch's probability carries into the particles' weights.
  patchCdf_.assign(exitCount(), 0.0f);
  facePower_.assign(6 * items_->size(), 0.0f);
  for (size_t i = 0; i < items_->size(); ++i) {
    const Luminaire& lum = (*items_)[i];
    for (int f = 0; f < 6; ++f) {
      double sum = 0;
      for (uint32_t k = lum.firstPatch(f); k < lum.firstPatch(f + 1); ++k) {
        const Color c = lum.patchPower(k);
        sum += (double(c.x) + c.y + c.z) / 3.0;
        patchCdf_[exitFirst_[i] + k] = float(sum);
      }
      for (uint32_t k = lum.firstPatch(f); k < lum.firstPatch(f + 1); ++k)
        patchCdf_[exitFirst_[i] + k] = sum > 0 ? float(patchCdf_[exitFirst_[i] + k] / sum) : 0.0f;
      facePower_[6 * i + size_t(f)] = float(sum);
    }
  }
  // The same per direction bin, by radiance × area (what a patch sends into the bin, up to π/kBins).
  constexpr int B = Luminaire::kBins;
  binCdf_.assign(size_t(B) * exitCount(), 0.0f);
  faceBinPower_.assign(6 * size_t(B) * items_->size(), 0.0f);
  for (size_t i = 0; i < items_->size(); ++i) {
    const Luminaire& lum = (*items_)[i];
    for (int b = 0; b < B; ++b) {
      float* cdf = &binCdf_[size_t(B) * exitFirst_[i] + size_t(b) * lum.patchCount()];
      for (int f = 0; f < 6; ++f) {
        double sum = 0;
        for (uint32_t k = lum.firstPatch(f); k < lum.firstPatch(f + 1); ++k) {
          const float* r = &lum.radiance[3 * (size_t(B) * k + size_t(b))];
          sum += (double(r[0]) + r[1] + r[2]) / 3.0 * lum.patch(k).area;
          cdf[k] = float(sum);
        }
        for (uint32_t k = lum.firstPatch(f); k < lum.firstPatch(f + 1); ++k) cdf[k] = sum > 0 ? float(cdf[k] / sum) : 0.0f;
        faceBinPower_[(6 * i + size_t(f)) * B + size_t(b)] = float(sum);
      }
    }
  }
}

LuminaireBoxes::FaceWeights LuminaireBoxes::faceWeights(uint32_t i, const Vec3& x) const {
  FaceWeights w;
  w.power = facingPower(i, x, w.facing);
  const Luminaire& lum = (*items_)[i];
  for (int f = 0; f < 6; ++f) {
    w.toward[f] = 0.0f, w.bin[f] = -1;
    if (!w.facing[f] || !(facePower_[6 * i + size_t(f)] > 0.0f)) continue;
    const int a = f / 2;
    Vec3 centre = 0.5f * (lum.lo + lum.hi);
    centre[a] = (f & 1) ? lum.hi[a] : lum.lo[a];
    const Vec3 d = x - centre;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) continue;
    const Vec3 dir = d / std::sqrt(dist2);
    const int b = Luminaire::bin(f, dir);
    if (b < 0) continue;
    w.bin[f] = b;
    w.toward[f] = faceBinPower_[(6 * i + size_t(f)) * Luminaire::kBins + size_t(b)] * std::abs(dir[a]) / dist2;
    w.towardTotal += w.toward[f];
  }
  return w;
}

float LuminaireBoxes::probability(const FaceWeights& w, uint32_t i, uint32_t patch) const {
  const Luminaire& lum = (*items_)[i];
  const int f = lum.patch(patch).face;
  if (!(w.power > 0.0f) || !w.facing[f]) return 0.0f;
  auto width = [&](const float* cdf) { return cdf[patch] - (patch > lum.firstPatch(f) ? cdf[patch - 1] : 0.0f); };
  const float byPower = facePower_[6 * i + size_t(f)] / w.power * width(&patchCdf_[exitFirst_[i]]);
  if (!(w.towardTotal > 0.0f)) return byPower;
  const float toward = w.bin[f] >= 0 ? w.toward[f] / w.towardTotal * width(binCdf(i, w.bin[f])) : 0.0f;
  return kPowerShare * byPower + (1.0f - kPowerShare) * toward;
}

float LuminaireBoxes::facingPower(uint32_t i, const Vec3& x, bool facing[6]) const {
  const Luminaire& lum = (*items_)[i];
  float total = 0.0f;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    facing[f] = (f & 1) ? x[a] > lum.hi[a] : x[a] < lum.lo[a];
    if (facing[f]) total += facePower_[6 * i + size_t(f)];
  }
  return total;
}

bool LuminaireBoxes::choosePatch(uint32_t i, const Vec3& x, float& u, uint32_t& patch, float& p) const {
  const FaceWeights w = faceWeights(i, x);
  if (!(w.power > 0.0f)) return false;
  // Towards x, or by power (always, where no face sends anything towards x in its centre's bin).
  const bool toward = w.towardTotal > 0.0f && u >= kPowerShare;
  if (w.towardTotal > 0.0f) u = toward ? (u - kPowerShare) / (1.0f - kPowerShare) : u / kPowerShare;
  u = std::clamp(u, 0.0f, 0x1.fffffep-1f);
  auto weight = [&](int f) { return toward ? w.toward[f] : w.facing[f] ? facePower_[6 * i + size_t(f)] : 0.0f; };
  float target = u * (toward ? w.towardTotal : w.power);
  int f = 0, last = -1;
  for (; f < 6; ++f) {
    if (!(weight(f) > 0.0f)) continue;
    last = f;
    if (target < weight(f)) break;
    target -= weight(f);
  }
  if (last < 0) return false;
  if (f == 6) f = last, target = weight(f) * 0x1.fffffep-1f;  // rounding at the top
  const float v = std::clamp(target / weight(f), 0.0f, 0x1.fffffep-1f);
  const Luminaire& lum = (*items_)[i];
  const float* cdf = toward ? binCdf(i, w.bin[f]) : &patchCdf_[exitFirst_[i]];
  const uint32_t begin = lum.firstPatch(f), end = lum.firstPatch(f + 1);
  const uint32_t k = uint32_t(std::upper_bound(cdf + begin, cdf + end - 1, v) - cdf);
  const float lo = k > begin ? cdf[k - 1] : 0.0f, width = cdf[k] - lo;
  if (!(width > 0.0f)) return false;
  patch = k;
  p = probability(w, i, k);
  u = std::clamp((v - lo) / width, 0.0f, 0x1.fffffep-1f);
  return p > 0.0f;
}

float LuminaireBoxes::patchProbability(uint32_t i, const Vec3& x, uint32_t patch) const {
  return probability(faceWeights(i, x), i, patch);
}

int LuminaireBoxes::containing(const Vec3& p) const {
  if (empty()) return -1;
  for (size_t i = 0; i < items_->size(); ++i)
    if ((*items_)[i].contains(p)) return int(i);
  return -1;
}

int LuminaireBoxes::entries(const Vec3& o, const Vec3& d, float tmax, Entry* out) const {
  if (empty()) return 0;
  int n = 0;
  for (size_t i = 0; i < items_->size(); ++i) {
    Entry e;
    if (!(*items_)[i].entry(o, d, tmax, e.t, e.face)) continue;
    e.luminaire = uint32_t(i);
    if (n == kMaxEntries && !(e.t < out[n - 1].t)) continue;  // full: keep the nearest
    int k = n < kMaxEntries ? n++ : n - 1;
    for (; k > 0 && out[k - 1].t > e.t; --k) out[k] = out[k - 1];  // nearest first
    out[k] = e;
  }
  return n;
}

uint32_t LuminaireBoxes::exitLuminaire(uint32_t e) const {
  return uint32_t(std::upper_bound(exitFirst_.begin(), exitFirst_.end(), e) - exitFirst_.begin()) - 1;
}

}  // namespace firstshot
