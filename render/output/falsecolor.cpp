// False colour: the colour map, scales, automatic ranges and ticks (render/output/falsecolor.h).
#include "render/output/falsecolor.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace firstshot::falsecolor {

namespace {

/// Control points of the colour map (8-bit sRGB), chosen for this project: violet, blue, teal,
/// green, yellow, each lighter than the one before; linear interpolation in between.
struct Stop {
  double t;
  double r, g, b;
};
constexpr Stop kStops[] = {{0.0, 48, 12, 80},    {0.2, 62, 54, 140},  {0.4, 38, 110, 150},
                           {0.6, 32, 158, 128},  {0.8, 128, 198, 70}, {1.0, 250, 232, 60}};

/// The value at quantile @p q ∈ [0, 1] of sorted @p v (nearest rank).
double quantile(const std::vector<double>& v, double q) {
  return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

}  // namespace

std::array<uint8_t, 3> colorMap(double t) {
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
  size_t k = 1;
  while (k + 1 < std::size(kStops) && t > kStops[k].t) ++k;
  const Stop &a = kStops[k - 1], &b = kStops[k];
  const double u = (t - a.t) / (b.t - a.t);
  auto mix = [u](double x, double y) { return uint8_t(std::lround(x + (y - x) * u)); };
  return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

double position(double value, const Range& range, Scale scale) {
  if (scale == Scale::Linear) return (value - range.min) / (range.max - range.min);
  if (!(value > 0)) return -HUGE_VAL;
  return std::log(value / range.min) / std::log(range.max / range.min);
}

double niceNumber(double x, bool up) {
  const double p = std::pow(10.0, std::floor(std::log10(x) + 1e-9));  // 10^k ≤ x, also for x = 10^k − ulp
  const double m = x / p;  // in [1, 10)
  if (up) return (m <= 1.0 + 1e-9 ? 1 : m <= 2 + 1e-9 ? 2 : m <= 5 + 1e-9 ? 5 : 10) * p;
  return (m >= 5 - 1e-9 ? 5 : m >= 2 - 1e-9 ? 2 : 1) * p;
}

Range autoRange(const std::vector<double>& values, Scale scale) {
  std::vector<double> v;
  v.reserve(values.size());
  for (double x : values)
    if (std::isfinite(x) && (scale == Scale::Linear || x > 0)) v.push_back(x);
  if (v.empty()) return {1, 10};
  std::sort(v.begin(), v.end());
  double lo = quantile(v, 0.01), hi = quantile(v, 0.99);
  if (scale == Scale::Log) {
    hi = niceNumber(hi, true);
    lo = niceNumber(std::max(lo, hi * 1e-6), false);
    if (!(lo < hi)) lo = niceNumber(hi / 10 * (1 + 1e-9), false);  // one decade below a constant field
    return {lo, hi};
  }
  if (!(hi > lo)) {  // a constant field: a range of one nice step around it
    const double step = niceNumber(std::max(std::abs(lo), 1e-30), true);
    return lo >= 0 && lo < step ? Range{0, step} : Range{std::floor(lo / step) * step, std::floor(lo / step) * step + step};
  }
  const double step = niceNumber((hi - lo) / 5, true);
  return {std::floor(lo / step + 1e-9) * step, std::ceil(hi / step - 1e-9) * step};
}

namespace {

/// Adds the ends of @p range to sorted ticks @p t unless a tick is already there.
std::vector<double> withEnds(std::vector<double> t, const Range& range, double eps) {
  auto near = [eps](double a, double b) { return std::abs(a - b) <= eps * std::max(std::abs(a), std::abs(b)); };
  if (t.empty() || !near(t.front(), range.min)) t.insert(t.begin(), range.min);
  if (!near(t.back(), range.max)) t.push_back(range.max);
  return t;
}

}  // namespace

std::vector<double> ticks(const Range& range, Scale scale, int count) {
  count = std::max(count, 2);
  std::vector<double> t;
  const double eps = 1e-9;
  if (scale == Scale::Linear) {
    const double step = niceNumber((range.max - range.min) / double(count - 1), true);
    for (double k = std::ceil(range.min / step - eps); k * step <= range.max - eps * step; ++k)
      if (k * step >= range.min + eps * step) t.push_back(std::abs(k) < 0.5 ? 0.0 : k * step);
    return withEnds(t, range, eps);
  }
  const double d0 = std::ceil(std::log10(range.min) - eps), d1 = std::floor(std::log10(range.max) + eps);
  const int decades = int(d1 - d0) + 1;
  const int every = std::max(1, (decades + count - 1) / count);
  for (double d = d0; d <= d1; d += every) t.push_back(std::pow(10.0, d));
  if (t.size() < 3) {  // fewer than three powers of ten: add 2 and 5 × 10^k
    for (double d = d0 - 1; d <= d1; ++d)
      for (double m : {2.0, 5.0}) {
        const double x = m * std::pow(10.0, d);
        if (x >= range.min * (1 - eps) && x <= range.max * (1 + eps)) t.push_back(x);
      }
    std::sort(t.begin(), t.end());
  }
  return withEnds(t, range, eps);
}

std::string label(double value) {
  if (value == 0) return "0";
  const double a = std::abs(value);
  if (a >= 1e5 || a < 1e-3) return fmt::format("{:.2g}", value);
  return fmt::format("{:.6g}", value);  // 0.5, 200, 20000
}

}  // namespace firstshot::falsecolor
