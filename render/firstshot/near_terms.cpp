// Near first-shot terms in structure-of-arrays blocks (render/firstshot/near_terms.h).
#include "render/firstshot/near_terms.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace firstshot {

void NearTerms::clear() {
  blockStart_.assign(1, 0);
  for (auto* v : {&px_, &py_, &pz_, &nx_, &ny_, &nz_, &point_, &cr_, &cg_, &cb_}) v->clear();
}

void NearTerms::add(const Vec3& position, const Vec3& normal, float point, const Color& coefficient) {
  px_.push_back(position.x), py_.push_back(position.y), pz_.push_back(position.z);
  nx_.push_back(normal.x), ny_.push_back(normal.y), nz_.push_back(normal.z);
  point_.push_back(point);
  cr_.push_back(coefficient.x), cg_.push_back(coefficient.y), cb_.push_back(coefficient.z);
}

void NearTerms::addPoint(const Vec3& position, const Color& coefficient) {
  add(position, Vec3(0.0f), 1.0f, coefficient);
}

void NearTerms::addArea(const Vec3& position, const Vec3& normal, const Color& coefficient) {
  add(position, normal, 0.0f, coefficient);
}

void NearTerms::endPatch() {
  while (px_.size() % kLanes != 0) add(Vec3(0.0f), Vec3(0.0f), 0.0f, Color(0.0f));
  blockStart_.push_back(uint32_t(px_.size() / kLanes));
}

Color NearTerms::sum(uint32_t patch, const Vec3& x, const Vec3& n) const {
  // With d = position − x: cosθ_x·d = d·n, cosθ_L·d = −d·n_L (area) or d (point), so the kernel is
  // (d·n)(cosθ_L·d)/d⁴. Lane-wise sums in a fixed order, the same arithmetic with or without SSE.
#if defined(__SSE2__)
  const uint32_t first = blockStart_[patch], last = blockStart_[patch + 1];
  float r[kLanes] = {}, g[kLanes] = {}, b[kLanes] = {};
  static_assert(kLanes == 4, "one SSE register per block");
  const __m128 xx = _mm_set1_ps(x.x), xy = _mm_set1_ps(x.y), xz = _mm_set1_ps(x.z);
  const __m128 nx = _mm_set1_ps(n.x), ny = _mm_set1_ps(n.y), nz = _mm_set1_ps(n.z);
  const __m128 zero = _mm_setzero_ps(), tiny = _mm_set1_ps(1e-18f), one = _mm_set1_ps(1.0f);
  __m128 sr = zero, sg = zero, sb = zero;
  for (uint32_t block = first; block < last; ++block) {
    const size_t o = size_t(block) * kLanes;
    const __m128 dx = _mm_sub_ps(_mm_loadu_ps(&px_[o]), xx), dy = _mm_sub_ps(_mm_loadu_ps(&py_[o]), xy),
                 dz = _mm_sub_ps(_mm_loadu_ps(&pz_[o]), xz);
    const __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    const __m128 cosX = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, nx), _mm_mul_ps(dy, ny)), _mm_mul_ps(dz, nz));
    const __m128 dotL = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, _mm_loadu_ps(&nx_[o])), _mm_mul_ps(dy, _mm_loadu_ps(&ny_[o]))),
                                   _mm_mul_ps(dz, _mm_loadu_ps(&nz_[o])));
    const __m128 cosL = _mm_sub_ps(_mm_mul_ps(_mm_loadu_ps(&point_[o]), _mm_sqrt_ps(d2)), dotL);
    const __m128 inv = _mm_div_ps(one, _mm_max_ps(d2, tiny));
    const __m128 k = _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(_mm_max_ps(cosX, zero), _mm_max_ps(cosL, zero)), inv), inv);
    sr = _mm_add_ps(sr, _mm_mul_ps(_mm_loadu_ps(&cr_[o]), k));
    sg = _mm_add_ps(sg, _mm_mul_ps(_mm_loadu_ps(&cg_[o]), k));
    sb = _mm_add_ps(sb, _mm_mul_ps(_mm_loadu_ps(&cb_[o]), k));
  }
  _mm_storeu_ps(r, sr), _mm_storeu_ps(g, sg), _mm_storeu_ps(b, sb);
  Color e(0.0f);
  for (uint32_t l = 0; l < kLanes; ++l) e += Color(r[l], g[l], b[l]);
  return e;
#else
  return sumPortable(patch, x, n);
#endif
}

Color NearTerms::sumPortable(uint32_t patch, const Vec3& x, const Vec3& n) const {
  float r[kLanes] = {}, g[kLanes] = {}, b[kLanes] = {};
  for (uint32_t block = blockStart_[patch], last = blockStart_[patch + 1]; block < last; ++block) {
    const size_t o = size_t(block) * kLanes;
    for (uint32_t l = 0; l < kLanes; ++l) {
      const float dx = px_[o + l] - x.x, dy = py_[o + l] - x.y, dz = pz_[o + l] - x.z;
      const float d2 = (dx * dx + dy * dy) + dz * dz;
      const float cosX = (dx * n.x + dy * n.y) + dz * n.z;
      const float dotL = (dx * nx_[o + l] + dy * ny_[o + l]) + dz * nz_[o + l];
      const float cosL = point_[o + l] * std::sqrt(d2) - dotL;
      const float inv = 1.0f / std::max(d2, 1e-18f);
      const float k = std::max(cosX, 0.0f) * std::max(cosL, 0.0f) * inv * inv;
      r[l] += cr_[o + l] * k, g[l] += cg_[o + l] * k, b[l] += cb_[o + l] * k;
    }
  }
  Color e(0.0f);
  for (uint32_t l = 0; l < kLanes; ++l) e += Color(r[l], g[l], b[l]);
  return e;
}

}  // namespace firstshot
