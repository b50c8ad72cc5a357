// Warps (common/sampling/sampling.h) and the deterministic sampler (common/sampling/rng.h).
//
// Thresholds: each chi-square test uses a fixed seed and requires p > kAlpha, the Šidák-corrected
// level for a family-wise false-rejection probability of 1% over the 15 acceptance tests of this
// file (kAlpha = 6.7e-4). The seed is fixed, so a pass is reproducible; a wrong density gives
// p < 1e-6 (see the negative controls). Densities must
// integrate to 1 within 1e-4 (midpoint rule on equal-area cells). Correlations of independent streams
// must stay below 4/√n (4 standard deviations of the null distribution).
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "tests/direction_histogram.h"
#include "tests/stats.h"

namespace firstshot {
namespace {

using test::chiSquareTest;
using test::RunningStats;
using test::SphereHistogram;

const double kAlpha = test::sidakAlpha(0.01, 15);
constexpr int kSamples = 400000;
constexpr uint64_t kSeed = 12345;

using Warp = std::function<Vec3(const Vec2&)>;
using Pdf = std::function<double(const Vec3&)>;

/// Draws kSamples directions with @p warp, bins them (cells uniform in z ∈ [zMin, 1] and φ about +z,
/// one cell below zMin) and tests them against @p pdf.
test::ChiSquareResult warpChiSquare(const Warp& warp, const Pdf& pdf, double zMin = -1.0,
                                    const Frame& frame = Frame()) {
  SphereHistogram h(20, 40, frame, zMin);
  Sampler rng(kSeed, 0, 0);
  for (int i = 0; i < kSamples; ++i) {
    const Vec3 w = warp(rng.next2D());
    EXPECT_NEAR(glm::length(w), 1.0f, 1e-5f);
    h.add(w);
  }
  return chiSquareTest(h.counts(), h.expected(pdf, 6));
}

/// ∫pdf dω over the sphere (midpoint rule, 256×32 cells above zMin with 8×8 points each).
double pdfIntegral(const Pdf& pdf, double zMin) {
  double integral = 0.0;
  SphereHistogram(256, 32, Frame(), zMin).expected(pdf, 8, &integral);
  return integral;
}

struct WarpCase {
  const char* name;
  Warp warp;
  Pdf pdf;
  double zMin = -1.0;  ///< zoom of the histogram onto the pole for narrow lobes
};

std::vector<WarpCase> warpCases() {
  std::vector<WarpCase> cases = {
      {"sphere", squareToUniformSphere, [](const Vec3&) { return double(squareToUniformSpherePdf()); }},
      {"hemisphere", squareToUniformHemisphere, [](const Vec3& w) { return double(squareToUniformHemispherePdf(w)); }},
      {"cosine", squareToCosineHemisphere, [](const Vec3& w) { return double(squareToCosineHemispherePdf(w)); }},
  };
  for (float n : {0.0f, 1.0f, 3.0f, 20.0f, 100.0f}) {
    // Zoom so that 98% of the lobe lies in the fine cells: P(cos α < z) = z^{n+1}.
    const double zMin = n >= 3 ? std::pow(0.02, 1.0 / (n + 1.0)) : -1.0;
    cases.push_back({"phong", [n](const Vec2& u) { return squareToPhongLobe(u, n); },
                     [n](const Vec3& w) { return double(squareToPhongLobePdf(w.z, n)); }, zMin});
  }
  return cases;
}

TEST(Warps, PdfIntegratesToOne) {
  for (const auto& c : warpCases()) EXPECT_NEAR(pdfIntegral(c.pdf, c.zMin), 1.0, 1e-4) << c.name;
}

TEST(Warps, ChiSquareAgainstPdf) {
  for (const auto& c : warpCases()) {
    const auto r = warpChiSquare(c.warp, c.pdf, c.zMin);
    std::printf("chi-square %-10s: %8.1f, dof %3d, p = %.4f\n", c.name, r.statistic, r.dof, r.pValue);
    EXPECT_GT(r.pValue, kAlpha) << c.name << ": chi2 = " << r.statistic << ", dof = " << r.dof;
    EXPECT_GT(r.cells, 300) << c.name;
  }
}

TEST(Warps, ChiSquareRejectsWrongPdf) {
  // Negative controls: the test must have power against plausible mistakes.
  auto r = warpChiSquare(squareToUniformHemisphere, [](const Vec3& w) { return double(squareToCosineHemispherePdf(w)); });
  EXPECT_LT(r.pValue, 1e-6);
  r = warpChiSquare([](const Vec2& u) { return squareToPhongLobe(u, 3.0f); },
                    [](const Vec3& w) { return double(squareToPhongLobePdf(w.z, 3.5f)); });
  EXPECT_LT(r.pValue, 1e-6);
}

TEST(Warps, PhongLobeAroundAxis) {
  // The lobe around an arbitrary axis has the density of cos α measured against that axis.
  const Vec3 axis = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));
  const float n = 10.0f;
  const auto r = warpChiSquare([&](const Vec2& u) { return samplePhongLobe(axis, n, u); },
                               [&](const Vec3& w) { return double(squareToPhongLobePdf(glm::dot(w, axis), n)); },
                               0.6, Frame(axis));
  EXPECT_GT(r.pValue, kAlpha) << r.statistic;
}

TEST(Warps, ConcentricDisk) {
  // Equal-area cells in (r², θ): expected count kSamples/cells each.
  const int nr = 20, nt = 40;
  std::vector<double> obs(nr * nt, 0.0), exp(nr * nt, double(kSamples) / (nr * nt));
  Sampler rng(kSeed, 1, 0);
  for (int i = 0; i < kSamples; ++i) {
    const Vec2 p = squareToUniformDiskConcentric(rng.next2D());
    const double r2 = double(p.x) * p.x + double(p.y) * p.y;
    ASSERT_LE(r2, 1.0 + 1e-6);
    double t = std::atan2(double(p.y), double(p.x));
    if (t < 0) t += 2 * kPi;
    const int ir = std::min(nr - 1, int(r2 * nr)), it = std::min(nt - 1, int(t / (2 * kPi) * nt));
    obs[ir * nt + it] += 1;
  }
  const double p = chiSquareTest(obs, exp).pValue;
  EXPECT_GT(p, kAlpha);
  std::printf("concentric disk: p = %.4f\n", p);
  // Density integrates to 1 over [-1,1]² (midpoint rule; the rim is the only error).
  const int g = 2048;
  double sum = 0;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j)
      sum += squareToUniformDiskConcentricPdf(Vec2(-1 + (i + 0.5f) * 2.0f / g, -1 + (j + 0.5f) * 2.0f / g));
  EXPECT_NEAR(sum * 4.0 / (double(g) * g), 1.0, 1e-4);
}

TEST(Warps, QuarterSinCosMatchesTheLibrary) {
  // The polynomial sin/cos behind the concentric mapping, on a fine grid over [−π/4, π/4].
  double worst = 0;
  for (int i = -4096; i <= 4096; ++i) {
    const float t = float(i) / 4096.0f * 0.25f * kPiF;
    float c, s;
    detail::sinCosQuarter(t, c, s);
    worst = std::max({worst, std::abs(double(c) - std::cos(double(t))), std::abs(double(s) - std::sin(double(t)))});
  }
  EXPECT_LT(worst, 4e-7);
  std::printf("quarter sin/cos: max abs error %.2e\n", worst);
  // The disk mapping's sector corners land on the unit circle.
  for (const Vec2 u : {Vec2(1, 1), Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(1, 0.5f), Vec2(0.5f, 1)}) {
    const Vec2 p = squareToUniformDiskConcentric(u);
    EXPECT_NEAR(double(p.x) * p.x + double(p.y) * p.y, 1.0, 1e-6) << u.x << "," << u.y;
  }
  EXPECT_EQ(squareToUniformDiskConcentric(Vec2(0.5f, 0.5f)), Vec2(0.0f));
}

TEST(Warps, UniformTriangle) {
  // Cells of a g×g grid over the (b1, b2) parameter square; the triangle b1 + b2 ≤ 1 has area 1/2,
  // density 2: inner cells expect 2h², diagonal cells h², cells outside 0.
  const int g = 32;
  const double h = 1.0 / g;
  std::vector<double> obs(g * g, 0.0), exp(g * g, 0.0);
  double expTotal = 0.0;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const double mass = (i + j + 2 <= g) ? 2 * h * h : (i + j + 1 == g ? h * h : 0.0);
      exp[i * g + j] = mass * kSamples;
      expTotal += mass;
    }
  EXPECT_NEAR(expTotal, 1.0, 1e-12);  // the density integrates to 1 exactly on this grid
  Sampler rng(kSeed, 2, 0);
  for (int k = 0; k < kSamples; ++k) {
    const Vec3 b = squareToUniformTriangle(rng.next2D());
    ASSERT_GE(b.x, 0.0f);
    ASSERT_GE(b.y, 0.0f);
    ASSERT_GE(b.z, 0.0f);
    ASSERT_NEAR(b.x + b.y + b.z, 1.0f, 1e-6f);
    obs[std::min(g - 1, int(b.y * g)) * g + std::min(g - 1, int(b.z * g))] += 1;
  }
  EXPECT_GT(chiSquareTest(obs, exp).pValue, kAlpha);
  EXPECT_FLOAT_EQ(squareToUniformTrianglePdf(0.25f), 4.0f);
}

TEST(Warps, StratifiedCosineCellsAndDensity) {
  // Every sample lies in its cell; pooled over cells the directions have density cosθ/π.
  const int M = 10, N = 20;
  SphereHistogram h(20, 40);
  Sampler rng(kSeed, 3, 0);
  const int rounds = kSamples / (M * N);
  for (int r = 0; r < rounds; ++r)
    for (int j = 0; j < M; ++j)
      for (int k = 0; k < N; ++k) {
        const Vec3 w = squareToCosineHemisphereStratum(j, k, M, N, rng.next2D());
        const float sin2 = 1.0f - w.z * w.z;
        ASSERT_GE(sin2, float(j) / M - 1e-5f);
        ASSERT_LE(sin2, float(j + 1) / M + 1e-5f);
        double phi = std::atan2(double(w.y), double(w.x));
        if (phi < 0) phi += 2 * kPi;
        ASSERT_GE(phi, 2 * kPi * k / N - 1e-4);
        ASSERT_LE(phi, 2 * kPi * (k + 1) / N + 1e-4);
        h.add(w);
      }
  const auto exp = h.expected([](const Vec3& w) { return double(squareToCosineHemispherePdf(w)); }, 6);
  EXPECT_GT(chiSquareTest(h.counts(), exp).pValue, kAlpha);
}

TEST(Warps, StratifiedCosineReducesVariance) {
  // Irradiance E = ∫ L cosθ dω of the smooth L = 1 + z² + 0.5x is 1.5π. Estimate it with M×N = 128
  // rays, stratified (π/(MN)·ΣL) or independent cosine samples (π·mean L), 2000 times each.
  const int M = 8, N = 16, reps = 2000;
  const auto L = [](const Vec3& w) { return 1.0 + double(w.z) * w.z + 0.5 * w.x; };
  const double exact = 1.5 * kPi;
  RunningStats strat, iid;
  for (int r = 0; r < reps; ++r) {
    Sampler a(kSeed, 4, r), b(kSeed, 5, r);
    double sa = 0, sb = 0;
    for (int j = 0; j < M; ++j)
      for (int k = 0; k < N; ++k) {
        sa += L(squareToCosineHemisphereStratum(j, k, M, N, a.next2D()));
        sb += L(squareToCosineHemisphere(b.next2D()));
      }
    strat.add(kPi * sa / (M * N));
    iid.add(kPi * sb / (M * N));
  }
  EXPECT_NEAR(strat.mean, exact, 3 * strat.standardError());
  EXPECT_NEAR(iid.mean, exact, 3 * iid.standardError());
  // Stratification must cut the variance by at least 4× (measured ≈ 10× or more).
  EXPECT_LT(strat.variance(), 0.25 * iid.variance())
      << "stratified " << strat.variance() << " vs independent " << iid.variance();
  std::printf("stratified %.3g vs independent %.3g: variance ratio %.1f\n", strat.variance(), iid.variance(),
              iid.variance() / strat.variance());
}

// ---- Sampler ----

TEST(Sampler, SameKeysSameNumbers) {
  Sampler a(7, 1234, 56, 2), b(7, 1234, 56, 2);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next1D(), b.next1D());
  Sampler c(7, 1234, 56, 2);
  c.setDimension(500);
  Sampler d(7, 1234, 56, 2);
  for (int i = 0; i < 500; ++i) d.next1D();
  EXPECT_EQ(c.next1D(), d.next1D());
  EXPECT_EQ(c.dimension(), 501u);
  EXPECT_EQ(hashToUnit(1, 2, 3), hashToUnit(1, 2, 3));
  EXPECT_NE(hashToUnit(1, 2, 3), hashToUnit(1, 3, 2));  // order matters
}

TEST(Sampler, DocumentedKeying) {
  // The formula in rng.h, restated: key = mix(mix(mix(mix(seed ^ salt) ^ pixel) ^ sample) ^ stream),
  // x_d = mix(key + (d+1)·0x9e3779b97f4a7c15), u_d = (x_d >> 40)·2^-24.
  const uint64_t seed = 1, pixel = 2, sample = 3, stream = 4;
  uint64_t key = Hasher::mix(seed ^ 0x6a09e667f3bcc909ull);
  key = Hasher::mix(Hasher::mix(Hasher::mix(key ^ pixel) ^ sample) ^ stream);
  Sampler s(seed, pixel, sample, stream);
  EXPECT_EQ(s.key(), key);
  for (uint64_t d = 0; d < 4; ++d) {
    const uint64_t x = Hasher::mix(key + (d + 1) * 0x9e3779b97f4a7c15ull);
    EXPECT_EQ(s.next1D(), float(x >> 40) * 0x1p-24f);
  }
  EXPECT_EQ(hashToUnit(seed, pixel, sample, stream), float(key >> 40) * 0x1p-24f);
}

TEST(Sampler, NeverReturnsOne) {
  EXPECT_LT(bitsToUnitFloat(~0ull), 1.0f);
  EXPECT_LT(bitsToUnitDouble(~0ull), 1.0);
  EXPECT_EQ(bitsToUnitFloat(0), 0.0f);
  Sampler s(1, 0, 0);
  for (int i = 0; i < 100000; ++i) {
    const float u = s.next1D();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    ASSERT_LT(s.nextIndex(7), 7u);
  }
}

/// First dimension of sampler(i) for i = 0..n-1, with a key built by @p make.
template <typename Make>
std::vector<double> firstDims(int n, Make make) {
  std::vector<double> v(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<size_t>(i)] = make(i).next1D();
  return v;
}

TEST(Sampler, NeighbouringKeysAreUncorrelated) {
  const int n = 200000;
  const double bound = 4.0 / std::sqrt(double(n));
  const auto base = firstDims(n, [](int i) { return Sampler(kSeed, uint64_t(i), 0); });
  struct Case {
    const char* what;
    std::vector<double> other;
  };
  const Case cases[] = {
      {"pixel+1", firstDims(n, [](int i) { return Sampler(kSeed, uint64_t(i) + 1, 0); })},
      {"sample+1", firstDims(n, [](int i) { return Sampler(kSeed, uint64_t(i), 1); })},
      {"seed+1", firstDims(n, [](int i) { return Sampler(kSeed + 1, uint64_t(i), 0); })},
      {"stream+1", firstDims(n, [](int i) { return Sampler(kSeed, uint64_t(i), 0, 1); })},
      {"dimension+1", firstDims(n, [](int i) {
         Sampler s(kSeed, uint64_t(i), 0);
         s.next1D();
         return s;
       })},
  };
  for (const auto& c : cases) {
    const double r = test::correlation(base, c.other);
    EXPECT_LT(std::abs(r), bound) << c.what << ": r = " << r;
    std::printf("correlation with %-11s: %+.5f (bound %.5f)\n", c.what, r, bound);
  }
  // Control: a sequence is perfectly correlated with itself, and the test sees a weak dependence.
  std::vector<double> mixed(base);
  for (size_t i = 0; i < mixed.size(); ++i) mixed[i] = 0.95 * cases[0].other[i] + 0.05 * base[i];
  EXPECT_GT(test::correlation(base, mixed), bound);
}

TEST(Sampler, UniformityChiSquare) {
  // 1D: 100 bins over the first dimension of consecutive pixels; 2D: next2D over 32×32 bins
  // along one sampler's dimensions; nextIndex(7).
  const int n = 1000000;
  std::vector<double> obs1(100, 0.0), obs2(32 * 32, 0.0), obs3(7, 0.0);
  Sampler walk(kSeed, 9, 9);
  for (int i = 0; i < n; ++i) {
    obs1[size_t(Sampler(kSeed, uint64_t(i), 3).next1D() * 100)] += 1;
    const Vec2 u = walk.next2D();
    obs2[size_t(u.x * 32) * 32 + size_t(u.y * 32)] += 1;
    obs3[walk.nextIndex(7)] += 1;
  }
  const auto p1 = chiSquareTest(obs1, std::vector<double>(100, n / 100.0)).pValue;
  const auto p2 = chiSquareTest(obs2, std::vector<double>(32 * 32, n / 1024.0)).pValue;
  const auto p3 = chiSquareTest(obs3, std::vector<double>(7, n / 7.0)).pValue;
  EXPECT_GT(p1, kAlpha);
  EXPECT_GT(p2, kAlpha);
  EXPECT_GT(p3, kAlpha);
  std::printf("uniformity p-values: 1D %.4f, 2D %.4f, nextIndex(7) %.4f\n", p1, p2, p3);
  // Control: a slightly non-uniform sequence (u^1.02) is rejected at the same sample size.
  std::vector<double> bad(100, 0.0);
  for (int i = 0; i < n; ++i) bad[size_t(std::pow(Sampler(kSeed, uint64_t(i), 3).next1D(), 1.02f) * 100)] += 1;
  EXPECT_LT(chiSquareTest(bad, std::vector<double>(100, n / 100.0)).pValue, 1e-6);
}

TEST(Stats, GammaQMatchesKnownValues) {
  // Chi-square survival function: Q(k/2, x/2). χ²(1) at 3.841459 → 0.05; χ²(10) at 23.209251 → 0.01;
  // χ²(2) at x → exp(−x/2).
  EXPECT_NEAR(test::gammaQ(0.5, 3.841459 / 2), 0.05, 1e-6);
  EXPECT_NEAR(test::gammaQ(5.0, 23.209251 / 2), 0.01, 1e-6);
  EXPECT_NEAR(test::gammaQ(1.0, 3.0), std::exp(-3.0), 1e-12);
  EXPECT_NEAR(test::gammaQ(400.0, 400.0), 0.5 - 0.0066, 2e-3);  // ≈ ½ − 1/(3√(2π·400))
}

}  // namespace
}  // namespace firstshot
