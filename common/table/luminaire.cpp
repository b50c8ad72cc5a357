// A luminaire's box, exit patches and exit distribution (luminaire.h).
#include "common/table/luminaire.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

uint32_t Luminaire::patchCount() const { return firstPatch(6); }

uint32_t Luminaire::firstPatch(int f) const {
  uint32_t k = 0;
  for (int g = 0; g < f; ++g) k += nu[size_t(g)] * nv[size_t(g)];
  return k;
}

ExitPatch Luminaire::patch(uint32_t k) const {
  int f = 0;
  while (f < 5 && k >= firstPatch(f + 1)) ++f;
  const uint32_t local = k - firstPatch(f);
  const uint32_t i = local % nu[size_t(f)], j = local / nu[size_t(f)];
  const int a = f / 2, u = (a + 1) % 3, v = (a + 2) % 3;
  const float du = (hi[u] - lo[u]) / float(nu[size_t(f)]), dv = (hi[v] - lo[v]) / float(nv[size_t(f)]);
  ExitPatch p;
  p.face = f;
  p.corner[a] = (f & 1) ? hi[a] : lo[a];
  p.corner[u] = lo[u] + float(i) * du;
  p.corner[v] = lo[v] + float(j) * dv;
  p.eu[u] = du;
  p.ev[v] = dv;
  p.normal = exitFaceNormal(f);
  p.area = du * dv;
  return p;
}

uint32_t Luminaire::patchAt(int f, const Vec3& p) const {
  const int a = f / 2, u = (a + 1) % 3, v = (a + 2) % 3;
  auto cell = [&](int axis, uint32_t n) {
    const float extent = hi[axis] - lo[axis];
    const float s = extent > 0.0f ? (p[axis] - lo[axis]) / extent : 0.0f;
    return std::min(n - 1, uint32_t(std::clamp(s, 0.0f, 1.0f) * float(n)));
  };
  return firstPatch(f) + cell(u, nu[size_t(f)]) + nu[size_t(f)] * cell(v, nv[size_t(f)]);
}

int Luminaire::bin(int f, const Vec3& w) {
  const int a = f / 2, u = (a + 1) % 3, v = (a + 2) % 3;
  const float cosT = (f & 1) ? w[a] : -w[a];
  if (!(cosT > 0.0f)) return -1;
  const float sin2 = std::max(0.0f, 1.0f - cosT * cosT);
  const int it = std::min(kThetaBins - 1, int(sin2 * float(kThetaBins)));
  const float phi = std::atan2(w[v], w[u]);  // (−π, π]
  const int ip = std::clamp(int((phi * (0.5f / kPiF) + 0.5f) * float(kPhiBins)), 0, kPhiBins - 1);
  return it * kPhiBins + ip;
}

Color Luminaire::radianceAt(uint32_t k, const Vec3& w) const {
  const ExitPatch p = patch(k);
  const int b = bin(p.face, w);
  if (b < 0) return Color(0.0f);
  const float* r = &radiance[3 * (size_t(kBins) * k + size_t(b))];
  return Color(r[0], r[1], r[2]);
}

Color Luminaire::patchPower(uint32_t k) const {
  Color sum(0.0f);
  const float* r = &radiance[3 * size_t(kBins) * k];
  for (int b = 0; b < kBins; ++b) sum += Color(r[3 * b], r[3 * b + 1], r[3 * b + 2]);
  return sum * (patch(k).area * kPiF / float(kBins));
}

namespace {

/// The unit direction @p w in continuous goniophotometric bin coordinates: rows (cos θ from +y, 0 at the top) in
/// [0, kGonioThetaBins], columns (φ = atan2(ω_z, ω_x)) in [0, kGonioPhiBins].
Vec2 gonioCoordinates(const Vec3& w) {
  return Vec2(std::clamp((1.0f - w.y) * 0.5f, 0.0f, 1.0f) * float(Luminaire::kGonioThetaBins),
              (std::atan2(w.z, w.x) * (0.5f / kPiF) + 0.5f) * float(Luminaire::kGonioPhiBins));
}

}  // namespace

int Luminaire::gonioBin(const Vec3& w) {
  const Vec2 c = gonioCoordinates(w);
  return std::clamp(int(c.x), 0, kGonioThetaBins - 1) * kGonioPhiBins + std::clamp(int(c.y), 0, kGonioPhiBins - 1);
}

Color Luminaire::intensityAt(const Vec3& w) const {
  if (intensity.size() != 3 * size_t(kGonioBins)) return Color(0.0f);
  // Bin centres at integers: rows clamped at the poles, columns periodic.
  const Vec2 c = gonioCoordinates(w) - Vec2(0.5f);
  const float s0 = std::floor(c.x), t0 = std::floor(c.y);
  const float fs = c.x - s0, ft = c.y - t0;
  const int rows[2] = {std::clamp(int(s0), 0, kGonioThetaBins - 1), std::clamp(int(s0) + 1, 0, kGonioThetaBins - 1)};
  const int c0 = (int(t0) % kGonioPhiBins + kGonioPhiBins) % kGonioPhiBins;
  const int cols[2] = {c0, (c0 + 1) % kGonioPhiBins};
  Color sum(0.0f);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const float weight = (i ? fs : 1.0f - fs) * (j ? ft : 1.0f - ft);
      const float* v = &intensity[3 * size_t(rows[i] * kGonioPhiBins + cols[j])];
      sum += weight * Color(v[0], v[1], v[2]);
    }
  return sum;
}

bool Luminaire::contains(const Vec3& p) const {
  return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
}

bool Luminaire::entry(const Vec3& o, const Vec3& d, float tmax, float& t, int& f) const {
  if (contains(o)) return false;
  float t0 = 0.0f, t1 = tmax;
  int face = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0f) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    const float inv = 1.0f / d[a];
    float tn = (lo[a] - o[a]) * inv, tf = (hi[a] - o[a]) * inv;
    int fn = 2 * a;  // entering through the low side when d[a] > 0
    if (tn > tf) std::swap(tn, tf), fn = 2 * a + 1;
    if (tn > t0) t0 = tn, face = fn;
    t1 = std::min(t1, tf);
    if (t0 > t1) return false;
  }
  if (face < 0 || !(t0 > 0.0f) || !(t0 < tmax)) return false;
  t = t0;
  f = face;
  return true;
}

}  // namespace firstshot
