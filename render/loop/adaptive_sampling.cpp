// The per-pixel sample targets of an adaptive round.
#include "render/loop/adaptive_sampling.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/sampling/rng.h"

namespace firstshot {

double pixelVariance(const Film& film, int x, int y) {
  if (film.samples(x, y) < 2) return 0.0;
  const Vec3d v = film.variance(x, y);
  const double m = (v.x + v.y + v.z) / 3.0;
  return std::isfinite(m) && m > 0.0 ? m : 0.0;
}

namespace {

/// pixelErrorWeight with the pixels' variances from @p variance(u, v).
template <class Variance>
double errorWeight(const Film& film, const PixelRect& rect, int x, int y, const Variance& variance) {
  const uint32_t n = film.samples(x, y);
  if (n == 0) return 0.0;
  double sum = 0.0;
  int count = 0;
  for (int v = std::max(rect.y0, y - 1); v <= std::min(rect.y1 - 1, y + 1); ++v)
    for (int u = std::max(rect.x0, x - 1); u <= std::min(rect.x1 - 1, x + 1); ++u)
      if (u != x || v != y) sum += variance(u, v), ++count;
  return count > 0 ? sum / double(count) / double(n) : 0.0;
}

}  // namespace

double pixelErrorWeight(const Film& film, const PixelRect& rect, int x, int y) {
  return errorWeight(film, rect, x, y, [&](int u, int v) { return pixelVariance(film, u, v); });
}

std::vector<uint32_t> adaptiveTargets(const Film& film, const std::vector<PixelRect>& tiles,
                                      const std::vector<uint64_t>& tileIndex, Comm& comm, uint64_t seed, int round,
                                      double extras) {
  // Each tile's sum in pixel order, then the tiles' sums in tile order over every rank: the same total,
  // bit for bit, however the tiles are dealt.
  // Each pixel's variance once, then its weight once (this rank's tiles).
  const uint64_t width = uint64_t(film.width());
  std::vector<double> variance(width * uint64_t(film.height()), 0.0), weight(variance.size(), 0.0);
  for (const PixelRect& r : tiles)
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) variance[uint64_t(y) * width + uint64_t(x)] = pixelVariance(film, x, y);
  ByteWriter out;
  out.put<uint64_t>(tiles.size());
  for (size_t t = 0; t < tiles.size(); ++t) {
    double sum = 0.0;
    for (int y = tiles[t].y0; y < tiles[t].y1; ++y)
      for (int x = tiles[t].x0; x < tiles[t].x1; ++x) {
        double& w = weight[uint64_t(y) * width + uint64_t(x)];
        w = errorWeight(film, tiles[t], x, y, [&](int u, int v) { return variance[uint64_t(v) * width + uint64_t(u)]; });
        sum += w;
      }
    out.put(tileIndex[t]);
    out.put(sum);
  }
  std::vector<std::pair<uint64_t, double>> sums;
  for (const Bytes& bytes : comm.allGather(out.bytes())) {
    ByteReader in(bytes);
    for (uint64_t n = in.get<uint64_t>(); n > 0; --n) {
      const uint64_t index = in.get<uint64_t>();
      sums.emplace_back(index, in.get<double>());
    }
  }
  std::sort(sums.begin(), sums.end());
  double total = 0.0;
  for (const auto& s : sums) total += s.second;

  std::vector<uint32_t> target(width * uint64_t(film.height()), 0);
  for (const PixelRect& r : tiles)
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        const uint64_t pixel = uint64_t(y) * width + uint64_t(x);
        double share = total > 0.0 ? extras * weight[pixel] / total : 0.0;
        share += double(hashToUnit(seed, pixel, uint64_t(round), 0xada97ULL));  // unbiased rounding
        const uint32_t extra = uint32_t(std::min<double>(kAdaptiveMaxExtra, std::floor(share)));
        target[pixel] = film.samples(x, y) + 1 + extra;
      }
  return target;
}

}  // namespace firstshot
