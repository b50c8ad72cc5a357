// The light tree (render/lights/light_tree.h): the probability a sample reports is the one pmf() gives
// for the same emitter, the probabilities sum to one, sampling frequencies follow them, and an
// emitter that can light a point is never left out.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>

#include "render/lights/light_tree.h"

using namespace firstshot;

namespace {

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    const Vec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

/// A mix of isotropic points, spots and one-sided triangles spread over a 10 m cube.
std::vector<LightBounds> randomEmitters(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> pos(-5.0f, 5.0f), power(0.1f, 10.0f), size(0.01f, 0.5f);
  std::vector<LightBounds> out;
  for (int i = 0; i < n; ++i) {
    LightBounds b;
    const Vec3 c(pos(rng), pos(rng), pos(rng));
    b.phi = power(rng);
    switch (i % 3) {
      case 0:  // point
        b.lo = b.hi = c;
        break;
      case 1:  // spot, 30°/45°
        b.lo = b.hi = c;
        b.w = randomUnit(rng);
        b.cosO = std::cos(glm::radians(30.0f));
        b.cosE = std::cos(glm::radians(15.0f));
        break;
      default: {  // triangle facing w
        const Vec3 a = c + size(rng) * randomUnit(rng), d = c + size(rng) * randomUnit(rng);
        b.lo = glm::min(c, glm::min(a, d));
        b.hi = glm::max(c, glm::max(a, d));
        b.w = randomUnit(rng);
        b.cosO = 1.0f;
        b.cosE = 0.0f;
      }
    }
    out.push_back(b);
  }
  return out;
}

}  // namespace

/// Trees with one emitter per leaf, and with leaves of up to 8 (every third emitter may not be grouped).
class LightTreeLeaves : public testing::TestWithParam<int> {};
INSTANTIATE_TEST_SUITE_P(LeafSizes, LightTreeLeaves, testing::Values(1, 8));

TEST_P(LightTreeLeaves, SampledPmfEqualsQueriedPmfAndSumsToAtMostOne) {
  std::mt19937 rng(7);
  const auto emitters = randomEmitters(300, rng);
  std::vector<uint32_t> groupable(emitters.size());
  for (size_t e = 0; e < groupable.size(); ++e) groupable[e] = e % 3 != 0;
  const LightTree tree(emitters, &groupable, GetParam());
  ASSERT_FALSE(tree.empty());
  EXPECT_LE(tree.depth(), 40);
  std::uniform_real_distribution<float> pos(-6.0f, 6.0f), u01(0.0f, 1.0f);
  int samples = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(pos(rng), pos(rng), pos(rng));
    const Vec3 n = k % 4 == 0 ? Vec3(0.0f) : randomUnit(rng);
    double sum = 0;
    for (uint32_t e = 0; e < emitters.size(); ++e) sum += tree.pmf(p, n, e);
    EXPECT_LE(sum, 1.0 + 1e-5) << "point " << k;
    for (int s = 0; s < 20; ++s) {
      uint32_t index;
      float pmf;
      if (!tree.sample(p, n, u01(rng), index, pmf)) continue;
      ++samples;
      ASSERT_LT(index, emitters.size());
      EXPECT_GT(pmf, 0.0f);
      EXPECT_FLOAT_EQ(pmf, tree.pmf(p, n, index)) << "point " << k << ", emitter " << index;
    }
  }
  EXPECT_GT(samples, 2000) << "most random points see some emitter: the comparisons above must not be vacuous";
}

/// Isotropic points and a receiver that takes light from everywhere: every emitter can light
/// the point, so no probability is lost and the pmfs sum to one.
TEST_P(LightTreeLeaves, PmfsSumToOneWhenEveryEmitterCanLight) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-5.0f, 5.0f), power(0.1f, 10.0f);
  std::vector<LightBounds> emitters(257);
  for (LightBounds& b : emitters) b.lo = b.hi = Vec3(pos(rng), pos(rng), pos(rng)), b.phi = power(rng);
  emitters[100].phi = 0.0f;  // never chosen
  const std::vector<uint32_t> groupable(emitters.size(), 1);
  const LightTree tree(emitters, &groupable, GetParam());
  if (GetParam() > 1) {
    EXPECT_LT(tree.depth(), LightTree(emitters).depth()) << "leaves of several emitters: a shallower tree";
  }
  for (int k = 0; k < 50; ++k) {
    const Vec3 p(pos(rng), pos(rng), pos(rng));
    double sum = 0;
    for (uint32_t e = 0; e < emitters.size(); ++e) sum += tree.pmf(p, Vec3(0.0f), e);
    EXPECT_NEAR(sum, 1.0, 1e-5);
    EXPECT_EQ(tree.pmf(p, Vec3(0.0f), 100), 0.0f);
  }
}

/// Stratified u over [0,1): the share of samples that pick each emitter is its pmf, up to the
/// stratification error (a descent of depth D maps u to emitters through at most D cuts per level).
TEST_P(LightTreeLeaves, SampleFrequenciesFollowThePmf) {
  std::mt19937 rng(11);
  const auto emitters = randomEmitters(60, rng);
  const std::vector<uint32_t> groupable(emitters.size(), 1);
  const LightTree tree(emitters, &groupable, GetParam());
  const Vec3 p(0.3f, -0.2f, 0.1f), n = glm::normalize(Vec3(0.2f, 1.0f, -0.1f));
  const int N = 200000;
  std::vector<int> count(emitters.size(), 0);
  int ok = 0;
  for (int i = 0; i < N; ++i) {
    uint32_t index;
    float pmf;
    if (tree.sample(p, n, (float(i) + 0.5f) / float(N), index, pmf)) ++count[index], ++ok;
  }
  double sum = 0;
  for (uint32_t e = 0; e < emitters.size(); ++e) {
    const double expected = tree.pmf(p, n, e);
    sum += expected;
    EXPECT_NEAR(double(count[e]) / N, expected, 2e-4 + 1e-3 * expected) << "emitter " << e;
  }
  EXPECT_NEAR(double(ok) / N, sum, 1e-3);
}

/// The rest of u (NEE reuses it for the point on the chosen emitter): for stratified u,
/// the rests of the samples that pick one emitter are themselves stratified over [0,1), so the
/// choice and the point share one stratified dimension. Checked as a histogram of 8 bins per emitter.
TEST_P(LightTreeLeaves, RestIsUniformWithinEachChoice) {
  std::mt19937 rng(12);
  const auto emitters = randomEmitters(60, rng);
  // The same random tree as the test above's, built in place so that each test reads on its own.
  const std::vector<uint32_t> groupable(emitters.size(), 1);
  const LightTree tree(emitters, &groupable, GetParam());
  const Vec3 p(0.3f, -0.2f, 0.1f), n = glm::normalize(Vec3(0.2f, 1.0f, -0.1f));
  const int N = 200000, kBins = 8;
  std::vector<int> bins(emitters.size() * kBins, 0), count(emitters.size(), 0);
  for (int i = 0; i < N; ++i) {
    uint32_t index;
    float pmf, rest = -1.0f;
    if (!tree.sample(p, n, (float(i) + 0.5f) / float(N), index, pmf, &rest)) continue;
    ASSERT_GE(rest, 0.0f);
    ASSERT_LT(rest, 1.0f);
    ++bins[index * kBins + std::min(kBins - 1, int(rest * kBins))];
    ++count[index];
  }
  for (uint32_t e = 0; e < emitters.size(); ++e) {
    if (count[e] < 800) continue;  // too few samples for 8 bins to be meaningful
    for (int b = 0; b < kBins; ++b)  // stratified: each bin within a few samples of its share
      EXPECT_NEAR(bins[e * kBins + b], count[e] / double(kBins), 3.0 + 0.01 * count[e])
          << "emitter " << e << " bin " << b;
  }
}

/// A one-sided triangle facing the receiver, seen within its hemisphere, always has a chance;
/// one that faces away, or lies below the receiver's horizon, has none.
TEST(LightTree, ConservativeAndCulling) {
  std::vector<LightBounds> emitters;
  auto triangle = [](const Vec3& c, const Vec3& w) {
    LightBounds b;
    b.lo = c - Vec3(0.1f);
    b.hi = c + Vec3(0.1f);
    b.w = w;
    b.cosO = 1.0f;
    b.cosE = 0.0f;
    b.phi = 1.0f;
    return b;
  };
  emitters.push_back(triangle(Vec3(0, 2, 0), Vec3(0, -1, 0)));   // above, facing down: lights p
  emitters.push_back(triangle(Vec3(0, 2, 1), Vec3(0, 1, 0)));    // above, facing up: cannot
  emitters.push_back(triangle(Vec3(0, -2, 0), Vec3(0, 1, 0)));   // below p's horizon: cannot
  emitters.push_back(triangle(Vec3(3, 0.5f, 0), Vec3(-1, 0, 0)));  // to the side, facing p, above the horizon
  const LightTree tree(emitters);
  const Vec3 p(0.0f), n(0, 1, 0);
  EXPECT_GT(tree.pmf(p, n, 0), 0.0f);
  EXPECT_EQ(tree.pmf(p, n, 1), 0.0f);
  EXPECT_EQ(tree.pmf(p, n, 2), 0.0f);
  EXPECT_GT(tree.pmf(p, n, 3), 0.0f);
  EXPECT_LE(tree.pmf(p, n, 0) + tree.pmf(p, n, 3), 1.0f + 1e-6f);
  // The nearer, head-on emitter is preferred.
  EXPECT_GT(tree.pmf(p, n, 0), tree.pmf(p, n, 3));
}

TEST(LightTree, EmptyAndSingle) {
  const LightTree none(std::vector<LightBounds>{});
  uint32_t index;
  float pmf;
  EXPECT_TRUE(none.empty());
  EXPECT_FALSE(none.sample(Vec3(0.0f), Vec3(0, 1, 0), 0.5f, index, pmf));
  LightBounds b;
  b.lo = b.hi = Vec3(0, 1, 0);
  b.phi = 2.0f;
  const LightTree one(std::vector<LightBounds>{b});
  ASSERT_TRUE(one.sample(Vec3(0.0f), Vec3(0, 1, 0), 0.7f, index, pmf));
  EXPECT_EQ(index, 0u);
  EXPECT_EQ(pmf, 1.0f);
  EXPECT_EQ(one.pmf(Vec3(0.0f), Vec3(0, 1, 0), 0), 1.0f);
  // A tree that is a single leaf chooses by power without bounds (the BSDF then gives 0 below the
  // horizon, before any shadow ray); sample and pmf still agree.
  ASSERT_TRUE(one.sample(Vec3(0.0f), Vec3(0, -1, 0), 0.7f, index, pmf));
  EXPECT_EQ(pmf, one.pmf(Vec3(0.0f), Vec3(0, -1, 0), 0));
  // With two leaves the bounds cull: both emitters below the receiver's horizon.
  LightBounds c = b;
  c.lo = c.hi = Vec3(3, 1, 0);
  const LightTree two(std::vector<LightBounds>{b, c});
  EXPECT_FALSE(two.sample(Vec3(0.0f), Vec3(0, -1, 0), 0.7f, index, pmf)) << "below the receiver's horizon";
  EXPECT_EQ(two.pmf(Vec3(0.0f), Vec3(0, -1, 0), 0), 0.0f);
}

/// Visibility factors per grid cell change the probabilities, never their consistency: the pmf a
/// sample reports is still the one pmf() gives, and a node with factor ε keeps its emitters reachable.
TEST(LightTree, VisibilityFactorsKeepSampleAndPmfConsistent) {
  std::mt19937 rng(5);
  const auto emitters = randomEmitters(200, rng);
  const std::vector<uint32_t> groupable(emitters.size(), 1);
  LightTree tree(emitters, &groupable, 4);
  const auto shared = std::make_shared<VisibilityGrid>();
  VisibilityGrid& grid = *shared;
  grid.origin = Vec3(-6.0f);
  grid.cell = 3.0f;
  grid.nx = grid.ny = grid.nz = 4;
  grid.row.assign(64, -1);
  for (size_t c = 0; c < grid.row.size(); c += 2) grid.row[c] = int32_t(grid.rows++);  // every other cell has factors
  const int D = std::min(4, tree.depth());
  const std::vector<uint32_t> cut = tree.cut(D);
  ASSERT_GT(cut.size(), 4u);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), pos(-6.0f, 6.0f);
  std::vector<float> v(grid.rows * cut.size());
  for (float& x : v) x = u01(rng) < 0.3f ? 0.0f : u01(rng);
  tree.setVisibility(shared, D, v, 0.05f);
  const LightTree plain(emitters, &groupable, 4);  // the same tree without factors, built once
  int samples = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(pos(rng), pos(rng), pos(rng)), n = randomUnit(rng);
    for (uint32_t e = 0; e < emitters.size(); ++e) {
      if (plain.pmf(p, n, e) > 0.0f) {
        EXPECT_GT(tree.pmf(p, n, e), 0.0f) << "emitter " << e << " lost its chance";
      }
    }
    for (int s = 0; s < 10; ++s) {
      uint32_t index;
      float pmf;
      if (!tree.sample(p, n, u01(rng), index, pmf)) continue;
      ++samples;
      EXPECT_FLOAT_EQ(pmf, tree.pmf(p, n, index));
    }
  }
  EXPECT_GT(samples, 1000);
}
