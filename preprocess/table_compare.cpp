#include "preprocess/table_compare.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/patches/patches.h"

namespace firstshot {

namespace {

/// Φ_i = Σ_j A_j r_ij per light sample i.
std::vector<double> sampleFlux(const FirstShotTable& t) {
  std::vector<double> flux(t.samples.size(), 0.0);
  for (uint32_t j = 0; j < t.mesh.size(); ++j)
    for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k) flux[t.sampleIndex[k]] += t.mesh.patches[j].area * t.factor[k];
  return flux;
}

double relativeDifference(double test, double ref) { return ref > 0 ? std::abs(test - ref) / ref : (test == 0 ? 0.0 : INFINITY); }

}  // namespace

TableDifference compareTables(const FirstShotTable& ref, const FirstShotTable& test) {
  TableDifference d;
  d.sameSamples = ref.samples.size() == test.samples.size();
  for (size_t i = 0; d.sameSamples && i < ref.samples.size(); ++i)
    d.sameSamples = ref.samples[i].kind == test.samples[i].kind && ref.samples[i].position.x == test.samples[i].position.x &&
                    ref.samples[i].position.y == test.samples[i].position.y && ref.samples[i].position.z == test.samples[i].position.z;
  d.sameMesh = ref.mesh.size() == test.mesh.size() && hashPatches(ref.mesh) == hashPatches(test.mesh);
  if (!d.sameSamples) {
    d.maxSampleFlux = d.totalFlux = d.weightedL1 = d.maxFactor = INFINITY;
    return d;
  }
  const std::vector<double> a = sampleFlux(ref), b = sampleFlux(test);
  const double peak = a.empty() ? 0.0 : *std::max_element(a.begin(), a.end());
  double sumA = 0, sumB = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sumA += a[i], sumB += b[i];
    if (a[i] > 1e-6 * peak) d.maxSampleFlux = std::max(d.maxSampleFlux, relativeDifference(b[i], a[i]));
  }
  d.totalFlux = relativeDifference(sumB, sumA);
  if (!d.sameMesh) {
    d.weightedL1 = d.maxFactor = NAN;
    return d;
  }
  double diff = 0, mass = 0;
  for (uint32_t j = 0; j < ref.mesh.size(); ++j) {
    const double area = ref.mesh.patches[j].area;
    uint64_t p = ref.rowStart[j], q = test.rowStart[j];
    const uint64_t pe = ref.rowStart[j + 1], qe = test.rowStart[j + 1];
    while (p < pe || q < qe) {  // rows ascend by sample: merge
      const uint32_t si = p < pe ? ref.sampleIndex[p] : UINT32_MAX, ti = q < qe ? test.sampleIndex[q] : UINT32_MAX;
      const double r = si <= ti ? ref.factor[p] : 0.0, s = ti <= si ? test.factor[q] : 0.0;
      if (si <= ti) ++p;
      if (ti <= si) ++q;
      mass += area * r;
      if (r != s) {
        ++d.differingFactors;
        diff += area * std::abs(s - r);
        d.maxFactor = std::max(d.maxFactor, relativeDifference(s, r));
      }
    }
  }
  d.weightedL1 = mass > 0 ? diff / mass : (diff > 0 ? INFINITY : 0.0);
  return d;
}

}  // namespace firstshot
