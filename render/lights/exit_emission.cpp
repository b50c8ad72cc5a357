// Particles leaving the luminaires' exit patches (exit_emission.h).
#include "render/lights/exit_emission.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace fs {

namespace {

constexpr int kBins = Luminaire::kBins;

double meanOf(const float* rgb) { return (double(rgb[0]) + rgb[1] + rgb[2]) / 3.0; }

}  // namespace

ExitEmission::ExitEmission(const LuminaireBoxes& boxes) : boxes_(&boxes) {
  if (boxes.empty()) return;
  patches_.reserve(boxes.exitCount());
  binCdf_.assign(size_t(boxes.exitCount()) * kBins, 0.0);
  for (uint32_t i = 0; i < boxes.items().size(); ++i) {
    const Luminaire& lum = boxes.items()[i];
    for (uint32_t k = 0; k < lum.patchCount(); ++k) {
      const uint32_t e = boxes.exitFirst(i) + k;
      patches_.push_back(lum.patch(k));
      double sum = 0;
      double* cdf = &binCdf_[size_t(e) * kBins];
      for (int b = 0; b < kBins; ++b) {
        sum += std::max(0.0, meanOf(&lum.radiance[3 * (size_t(kBins) * k + size_t(b))]));
        cdf[b] = sum;
      }
      for (int b = 0; b < kBins; ++b) cdf[b] = sum > 0 ? cdf[b] / sum : 0.0;
      if (sum > 0) cdf[kBins - 1] = 1.0;
      // Σ_b mean(L_b)·A·π/kBins: mean RGB of Luminaire::patchPower.
      power_.push_back(sum * patches_.back().area * kPi / kBins);
    }
  }
}

bool ExitEmission::sampleDirection(uint32_t e, double uBin, const Vec2& uDir, ExitDirection& out) const {
  if (!(power_[e] > 0)) return false;
  const double* cdf = &binCdf_[size_t(e) * kBins];
  const int b = int(std::min<std::ptrdiff_t>(std::upper_bound(cdf, cdf + kBins, uBin) - cdf, kBins - 1));
  const double q = cdf[b] - (b > 0 ? cdf[b - 1] : 0.0);  // the bin's share of the patch's power
  if (!(q > 0)) return false;
  const int it = b / Luminaire::kPhiBins, ip = b % Luminaire::kPhiBins;
  const float sin2 = (float(it) + uDir.x) / float(Luminaire::kThetaBins);
  const float phi = kPiF * (2.0f * (float(ip) + uDir.y) / float(Luminaire::kPhiBins) - 1.0f);
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2)), sinT = std::sqrt(std::clamp(sin2, 0.0f, 1.0f));
  if (!(cosT > 0.0f)) return false;
  const ExitPatch& p = patches_[e];
  const int a = p.face / 2, u = (a + 1) % 3, v = (a + 2) % 3;
  out.d = Vec3(0.0f);
  out.d[a] = (p.face & 1) ? cosT : -cosT;
  out.d[u] = sinT * std::cos(phi);
  out.d[v] = sinT * std::sin(phi);
  out.pdf = float(q * kBins * kInvPi) * cosT;
  const uint32_t i = boxes_->exitLuminaire(e), k = e - boxes_->exitFirst(i);
  const float* r = &boxes_->items()[i].radiance[3 * (size_t(kBins) * k + size_t(b))];
  out.radiance = Color(r[0], r[1], r[2]);
  return out.pdf > 0.0f;
}

float ExitEmission::pdfDirection(uint32_t e, const Vec3& d) const {
  const ExitPatch& p = patches_[e];
  const int b = Luminaire::bin(p.face, d);
  if (b < 0 || !(power_[e] > 0)) return 0.0f;
  const double* cdf = &binCdf_[size_t(e) * kBins];
  const double q = cdf[b] - (b > 0 ? cdf[b - 1] : 0.0);
  return float(q * kBins * kInvPi) * std::abs(d[p.face / 2]);
}

}  // namespace fs
