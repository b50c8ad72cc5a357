// Particles leaving the luminaires' exit patches (exit_emission.h).
#include "render/lights/exit_emission.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace firstshot {

namespace {

constexpr int kBins = Luminaire::kBins;

double meanOf(const float* rgb) { return (double(rgb[0]) + rgb[1] + rgb[2]) / 3.0; }

}  // namespace

ExitEmission::ExitEmission(const LuminaireBoxes& boxes) : boxes_(&boxes) {
  if (boxes.empty()) return;
  patches_.reserve(boxes.exitCount());
  bins_.reserve(boxes.exitCount());
  std::vector<double> binPower(kBins);
  for (uint32_t i = 0; i < boxes.items().size(); ++i) {
    const Luminaire& lum = boxes.items()[i];
    for (uint32_t k = 0; k < lum.patchCount(); ++k) {
      patches_.push_back(lum.patch(k));
      for (int b = 0; b < kBins; ++b) binPower[size_t(b)] = meanOf(&lum.radiance[3 * (size_t(kBins) * k + size_t(b))]);
      bins_.emplace_back(binPower);
      // Σ_b mean(L_b)·A·π/kBins: mean RGB of Luminaire::patchPower.
      power_.push_back(bins_.back().total() * patches_.back().area * kPi / kBins);
    }
  }
}

bool ExitEmission::sampleDirection(uint32_t e, double uBin, const Vec2& uDir, ExitDirection& out) const {
  if (!(power_[e] > 0)) return false;
  const int b = int(bins_[e].sampleDiscrete(uBin));
  const double q = bins_[e].probability(size_t(b));  // the bin's share of the patch's power
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
  const double q = bins_[e].probability(size_t(b));
  return float(q * kBins * kInvPi) * std::abs(d[p.face / 2]);
}

Color ExitEmission::radiance(uint32_t e, const Vec3& d) const {
  const uint32_t i = boxes_->exitLuminaire(e);
  return boxes_->items()[i].radianceAt(e - boxes_->exitFirst(i), d);
}

}  // namespace firstshot
