// The irradiance cache store: Ward's weights (eq. 5) and "in front" test (eq. 6) on hand-made
// configurations, gradient extrapolation, octree placement (2aR < side ≤ 4aR) and search (the
// same records as a brute-force scan), separate levels, neighbour clamping, and concurrent use.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <thread>

#include "render/integrators/irradiance_cache/cache.h"

using namespace firstshot;

namespace {

IrradianceRecord record(const Vec3& p, const Vec3& n, float R, const Color& E = Color(1.0f)) {
  IrradianceRecord r;
  r.p = p;
  r.n = n;
  r.R = R;
  r.E = E;
  return r;
}

/// Brute-force version of IrradianceCache::lookup's acceptance over @p records.
IrradianceEstimate bruteForce(const std::vector<IrradianceRecord>& records, float a, float tol, const Vec3& p, const Vec3& n) {
  IrradianceEstimate est;
  for (const IrradianceRecord& r : records) {
    if (!(glm::dot(n, r.n) > 0.0f)) continue;
    const float w = std::min(irradianceWeight(r.p, r.n, r.radius(), p, n), 1e6f);
    if (!(w > 1.0f / a) || inFrontDistance(r.p, r.n, p, n) < -tol) continue;
    est.sum += w * r.E;
    est.weight += w;
    ++est.count;
  }
  return est;
}

}  // namespace

TEST(IrradianceWeight, MatchesEquation5OnHandMadeConfigurations) {
  const Vec3 up(0, 1, 0);
  // Same point and normal: infinite weight.
  EXPECT_TRUE(std::isinf(irradianceWeight(Vec3(0), up, 1.0f, Vec3(0), up)));
  // Coplanar, distance 0.1, R = 1: w = 1/0.1 = 10.
  EXPECT_NEAR(irradianceWeight(Vec3(0), up, 1.0f, Vec3(0.1f, 0, 0), up), 10.0, 1e-4);
  // Distance scales with R: 0.1 away with R = 0.5 gives 1/0.2.
  EXPECT_NEAR(irradianceWeight(Vec3(0), up, 0.5f, Vec3(0, 0, 0.1f), up), 5.0, 1e-4);
  // Same point, normal tilted by 60°: 1/√(1 − cos 60°) = √2.
  const Vec3 tilted(std::sin(glm::radians(60.0f)), std::cos(glm::radians(60.0f)), 0);
  EXPECT_NEAR(irradianceWeight(Vec3(0), up, 1.0f, Vec3(0), tilted), std::sqrt(2.0), 1e-5);
  // Both terms add: 0.05/0.5 + √(1 − cos 60°) = 0.1 + √0.5.
  EXPECT_NEAR(irradianceWeight(Vec3(0), up, 0.5f, Vec3(0.05f, 0, 0), tilted), 1.0 / (0.1 + std::sqrt(0.5)), 1e-5);
  // Acceptance w > 1/a: with a = 0.1 a coplanar record is valid strictly within 0.1·R.
  EXPECT_GT(irradianceWeight(Vec3(0), up, 1.0f, Vec3(0.099f, 0, 0), up), 10.0f);
  EXPECT_LT(irradianceWeight(Vec3(0), up, 1.0f, Vec3(0.101f, 0, 0), up), 10.0f);
}

TEST(IrradianceInFront, RejectsRecordsOnOccluders) {
  const Vec3 up(0, 1, 0);
  // Ward's Figure 4: P on the floor under a block; P_i on the block top above it is in front.
  EXPECT_LT(inFrontDistance(Vec3(0, 0.2f, 0), up, Vec3(0.05f, 0, 0), up), 0.0f);
  EXPECT_NEAR(inFrontDistance(Vec3(0, 0.2f, 0), up, Vec3(0.05f, 0, 0), up), -0.2, 1e-6);
  // A record below P (P on a step above it) is behind: accepted.
  EXPECT_NEAR(inFrontDistance(Vec3(0, -0.2f, 0), up, Vec3(0.05f, 0, 0), up), 0.2, 1e-6);
  // Coplanar: d = 0 exactly.
  EXPECT_EQ(inFrontDistance(Vec3(0, 0, 0), up, Vec3(0.3f, 0, -0.7f), up), 0.0f);
  // Two points of a sphere: the chord is perpendicular to the mean normal, d = 0.
  const Vec3 a = glm::normalize(Vec3(1, 2, 0.5f)), b = glm::normalize(Vec3(1.2f, 1.9f, 0.4f));
  EXPECT_NEAR(inFrontDistance(a, a, b, b), 0.0, 1e-6);
  // Through the cache: a record on the block top is not used on the floor beneath, however close.
  IrradianceCache cache(Vec3(-1), Vec3(1), {0.5f});
  cache.insert(0, record(Vec3(0, 0.01f, 0), up, 1.0f), false);
  EXPECT_FALSE(cache.covers(0, Vec3(0.001f, 0, 0), up));
  EXPECT_TRUE(cache.covers(0, Vec3(0.001f, 0.02f, 0), up));
}

TEST(IrradianceGradients, ExtrapolateLinearly) {
  IrradianceRecord r = record(Vec3(0), Vec3(0, 1, 0), 1.0f, Color(1.0f, 2.0f, 3.0f));
  r.gradT[0] = Vec3(1, 0, 0);
  r.gradT[1] = Vec3(0, 0, -2);
  r.gradR[2] = Vec3(0, 0, 4);
  // Move by (0.1, 0, 0.1) and rotate the normal by a small angle about z: N_i × N = (0, 0, −sin α).
  const float alpha = 0.05f;
  const Vec3 n(-std::sin(alpha), std::cos(alpha), 0);
  const Color e = extrapolateIrradiance(r, Vec3(0.1f, 0, 0.1f), n);
  EXPECT_NEAR(e[0], 1.0 + 0.1, 1e-6);
  EXPECT_NEAR(e[1], 2.0 - 0.2, 1e-6);
  EXPECT_NEAR(e[2], 3.0 + 4 * glm::cross(r.n, n).z, 1e-6);
  // Clamped at zero.
  EXPECT_EQ(extrapolateIrradiance(r, Vec3(-5.0f, 0, 0), r.n)[0], 0.0f);
}

TEST(IrradianceOctree, PlacesRecordsInNodesTwoToFourTimesTheirDomain) {
  const float a = 0.2f;
  IrradianceCache cache(Vec3(0), Vec3(4), {a});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> radii;
  for (int i = 0; i < 500; ++i) {
    const float R = std::exp(std::log(1e-3f) + u(rng) * std::log(1e4f));  // 1 mm .. 10 m
    radii.push_back(R);
    cache.insert(0, record(4.0f * Vec3(u(rng), u(rng), u(rng)), Vec3(0, 0, 1), R), false);
  }
  const std::vector<int> depth = cache.nodeDepths(0);
  ASSERT_EQ(depth.size(), radii.size());
  int atRoot = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    const float s = cache.nodeSize(depth[i]), domain = a * radii[i];
    EXPECT_GT(s, 2.0f * domain) << "record " << i;
    if (depth[i] == 0) {
      ++atRoot;  // a domain larger than a quarter of the cube stays at the root
      EXPECT_GT(domain, cache.nodeSize(1) / 2.0f);
    } else {
      EXPECT_LE(s, 4.0f * domain) << "record " << i;
    }
  }
  EXPECT_GT(atRoot, 0);
  EXPECT_LT(atRoot, 500);
}

TEST(IrradianceOctree, SearchFindsExactlyTheBruteForceSet) {
  const float a = 0.15f;
  IrradianceCache cache(Vec3(-1), Vec3(1), {a, 2 * a});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<IrradianceRecord> records;
  // Records on two planes and a sphere, with a wide range of radii (and a few tiny ones).
  for (int i = 0; i < 3000; ++i) {
    Vec3 p, n;
    switch (i % 3) {
      case 0: p = Vec3(u(rng), -1.0f, u(rng)), n = Vec3(0, 1, 0); break;
      case 1: p = Vec3(-1.0f, u(rng), u(rng)), n = Vec3(1, 0, 0); break;
      default: n = glm::normalize(Vec3(u(rng), u(rng), u(rng))), p = 0.5f * n; break;
    }
    const float R = 0.002f + 0.5f * (u(rng) + 1.0f) * (u(rng) + 1.0f);
    records.push_back(record(p, n, R, Color(u(rng) + 1.0f, 1.0f, 0.5f)));
    cache.insert(0, records.back(), false);
  }
  cache.insert(1, record(Vec3(0, -1, 0), Vec3(0, 1, 0), 10.0f), false);  // level 1 is separate
  EXPECT_EQ(cache.size(0), 3000u);
  EXPECT_EQ(cache.size(1), 1u);
  const float tol = 1e-5f * cache.extent();
  int queries = 0, found = 0;
  for (int q = 0; q < 3000; ++q) {
    // Queries near the records' surfaces, with normals jittered a little.
    const IrradianceRecord& near = records[size_t(q) % records.size()];
    const Vec3 p = near.p + 0.05f * Vec3(u(rng), u(rng), u(rng));
    const Vec3 n = glm::normalize(near.n + 0.1f * Vec3(u(rng), u(rng), u(rng)));
    IrradianceEstimate fast;
    cache.lookup(0, p, n, false, fast);
    const IrradianceEstimate slow = bruteForce(records, a, tol, p, n);
    ASSERT_EQ(fast.count, slow.count) << "query " << q;
    EXPECT_NEAR(fast.weight, slow.weight, 1e-6 * slow.weight + 1e-9);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fast.value()[c], slow.value()[c], 1e-4);
    ++queries;
    found += fast.count > 0;
  }
  fmt::print("{} of {} queries found records\n", found, queries);
  EXPECT_GT(found, queries / 4);  // the comparison is not vacuous
  EXPECT_LT(found, queries);
}

// freeze(): lookups over the compact copy give bit for bit the sums of the octree's lists (the same records in the same
// order: the render's images do not change), at both acceptances, with neighbour clamping and footprint clamps in the
// radii; an insert afterwards is seen at once (the copy is not read stale).
TEST(IrradianceOctree, AFrozenCopyFindsTheSameRecordsInTheSameOrder) {
  const float a = 0.15f;
  IrradianceCache cache(Vec3(-1), Vec3(1), {a});
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    const bool floor = i % 2 == 0;
    IrradianceRecord r = record(floor ? Vec3(u(rng), -1.0f, u(rng)) : 0.5f * glm::normalize(Vec3(u(rng), u(rng), u(rng))),
                                Vec3(0, 1, 0), 0.002f + 0.3f * (u(rng) + 1.0f), Color(u(rng) + 1.0f, 1.0f, 0.5f));
    if (!floor) r.n = glm::normalize(r.p);
    r.gradT[0] = Vec3(u(rng), u(rng), u(rng));
    if (i % 5 == 0) r.Rmin = 0.05f, r.Rmax = 0.2f;
    cache.insert(0, r, i % 3 != 0);  // neighbour clamping lowers earlier radii
  }
  std::vector<std::pair<Vec3, Vec3>> queries;
  for (int q = 0; q < 4000; ++q) {
    const bool floor = q % 2 == 0;
    const Vec3 p = floor ? Vec3(u(rng), -1.0f + 0.01f * u(rng), u(rng)) : 0.5f * glm::normalize(Vec3(u(rng), u(rng), u(rng)));
    queries.emplace_back(p, floor ? Vec3(0, 1, 0) : glm::normalize(p));
  }
  auto lookups = [&](float relax) {
    std::vector<IrradianceEstimate> out(queries.size());
    for (size_t q = 0; q < queries.size(); ++q) cache.lookup(0, queries[q].first, queries[q].second, true, out[q], relax);
    return out;
  };
  const std::vector<IrradianceEstimate> lists1 = lookups(1.0f), lists2 = lookups(2.0f);
  cache.freeze();
  const std::vector<IrradianceEstimate> frozen1 = lookups(1.0f), frozen2 = lookups(2.0f);
  int found = 0;
  for (size_t q = 0; q < queries.size(); ++q) {
    ASSERT_EQ(frozen1[q].count, lists1[q].count) << q;
    ASSERT_EQ(frozen2[q].count, lists2[q].count) << q;
    EXPECT_EQ(frozen1[q].weight, lists1[q].weight) << q;
    EXPECT_EQ(frozen2[q].weight, lists2[q].weight) << q;
    EXPECT_EQ(frozen1[q].sum, lists1[q].sum) << q;
    EXPECT_EQ(frozen2[q].sum, lists2[q].sum) << q;
    found += lists1[q].count > 0;
  }
  fmt::print("{} of {} queries found records\n", found, queries.size());
  EXPECT_GT(found, int(queries.size()) / 10);  // the comparison is not vacuous
  EXPECT_LT(found, int(queries.size()));
  // After an insert the lists serve again: a record where none was is found.
  size_t empty = 0;
  while (empty < queries.size() && frozen1[empty].count > 0) ++empty;
  ASSERT_LT(empty, queries.size());
  cache.insert(0, record(queries[empty].first, queries[empty].second, 0.1f), false);
  EXPECT_TRUE(cache.covers(0, queries[empty].first, queries[empty].second));
}

TEST(IrradianceOctree, NeighbourClampingBoundsRadiiByDistance) {
  IrradianceCache cache(Vec3(-1), Vec3(1), {0.2f});
  const Vec3 up(0, 1, 0);
  cache.insert(0, record(Vec3(0, 0, 0), up, 1.0f), true);     // open area
  cache.insert(0, record(Vec3(0.5f, 0, 0), up, 1.0f), true);  // open area
  cache.insert(0, record(Vec3(0.3f, 0, 0), up, 0.01f), true); // near a corner: shrinks its neighbours
  cache.insert(0, record(Vec3(0.32f, 0, 0), up, 5.0f), true); // large R next to it: clamped to 0.01 + 0.02
  const std::vector<IrradianceRecord> r = cache.records(0);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_FLOAT_EQ(r[0].R, 0.01f + 0.3f);
  EXPECT_FLOAT_EQ(r[1].R, 0.01f + 0.2f);
  EXPECT_FLOAT_EQ(r[2].R, 0.01f);
  EXPECT_NEAR(r[3].R, 0.03f, 1e-6);
  for (const auto& x : r)
    for (const auto& y : r) EXPECT_LE(x.R, y.R + glm::length(x.p - y.p) + 1e-6f);
  // Without clamping the radii stay.
  IrradianceCache plain(Vec3(-1), Vec3(1), {0.2f});
  plain.insert(0, record(Vec3(0, 0, 0), up, 1.0f), false);
  plain.insert(0, record(Vec3(0.3f, 0, 0), up, 0.01f), false);
  EXPECT_FLOAT_EQ(plain.records(0)[0].R, 1.0f);
  // The footprint clamp bounds the radius used: clamp(R, Rmin, Rmax).
  IrradianceRecord c = record(Vec3(0), up, 0.01f);
  c.Rmin = 0.05f;
  c.Rmax = 0.2f;
  EXPECT_FLOAT_EQ(c.radius(), 0.05f);
  c.R = 3.0f;
  EXPECT_FLOAT_EQ(c.radius(), 0.2f);
}

TEST(IrradianceOctree, ConcurrentInsertsAndLookups) {
  // Two writers and two readers on one cache; run under ASan/TSan-like conditions in CI. Every
  // record inserted is found at its own position afterwards, and readers never see a torn one.
  IrradianceCache cache(Vec3(-1), Vec3(1), {0.1f});
  const int perWriter = 4000;
  std::atomic<bool> done{false};
  std::atomic<long> seen{0};
  auto writer = [&](int id) {
    std::mt19937 rng(id);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < perWriter; ++i)
      cache.insert(0, record(Vec3(u(rng), 0.0f, u(rng)), Vec3(0, 1, 0), 0.05f + 0.2f * (u(rng) + 1.0f), Color(2.0f)), true);
  };
  auto reader = [&](int id) {
    std::mt19937 rng(100 + id);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    while (!done.load()) {
      IrradianceEstimate est;
      cache.lookup(0, Vec3(u(rng), 0.0f, u(rng)), Vec3(0, 1, 0), false, est);
      if (est.count > 0) {
        EXPECT_NEAR(est.value()[0], 2.0f, 1e-4f);
        ++seen;
      }
    }
  };
  std::thread r0(reader, 0), r1(reader, 1), w0(writer, 0), w1(writer, 1);
  w0.join();
  w1.join();
  done = true;
  r0.join();
  r1.join();
  EXPECT_EQ(cache.size(0), size_t(2 * perWriter));
  EXPECT_GT(seen.load(), 0);
  for (const IrradianceRecord& r : cache.records(0)) ASSERT_TRUE(cache.covers(0, r.p, r.n));
}
