// NearTerms (render/firstshot/near_terms.h): the per-point sum of a patch's near first-shot terms against the
// closed forms of a point light and an area-light vertex, its sides and padding, and the SSE sum
// against the portable one bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "render/firstshot/near_terms.h"

using namespace firstshot;

namespace {

/// Point light: Φ V cosθ_x / (4π d²) per channel, here with coefficient c = Φ V / 4π.
double pointKernel(const Vec3d& light, const Vec3d& x, const Vec3d& n) {
  const Vec3d d = light - x;
  const double d2 = glm::dot(d, d), c = glm::dot(d, n) / std::sqrt(d2);
  return c > 0 ? c / d2 : 0.0;
}

/// Area vertex with light normal nL: cosθ_x cosθ_L / d².
double areaKernel(const Vec3d& light, const Vec3d& nL, const Vec3d& x, const Vec3d& n) {
  const Vec3d d = light - x;
  const double d2 = glm::dot(d, d), len = std::sqrt(d2);
  const double cx = glm::dot(d, n) / len, cl = -glm::dot(d, nL) / len;
  return cx > 0 && cl > 0 ? cx * cl / d2 : 0.0;
}

}  // namespace

TEST(NearTerms, SumsMatchTheClosedFormsPerPatch) {
  NearTerms t;
  t.clear();
  // Patch 0: a point light and an area vertex facing down, over the floor y = 0.
  const Vec3 light(0.3f, 1.2f, -0.4f), vertex(-0.5f, 0.9f, 0.2f), down(0, -1, 0);
  t.addPoint(light, Color(2.0f, 1.0f, 0.5f));
  t.addArea(vertex, down, Color(0.25f, 0.5f, 1.0f));
  t.endPatch();
  t.endPatch();  // patch 1: nothing
  // Patch 2: five terms (two blocks, the second padded), one of them an area vertex facing up
  // (the floor is behind its light) and one point under the floor.
  for (int i = 0; i < 3; ++i) t.addPoint(Vec3(0.1f * i, 0.5f + 0.2f * i, 0.3f), Color(1.0f));
  t.addArea(Vec3(0.0f, 1.0f, 0.0f), Vec3(0, 1, 0), Color(1.0f));
  t.addPoint(Vec3(0.0f, -1.0f, 0.0f), Color(1.0f));
  t.endPatch();

  const Vec3 x(0.05f, 0.0f, -0.1f), up(0, 1, 0);
  const Color e0 = t.sum(0, x, up);
  const double kp = pointKernel(Vec3d(light), Vec3d(x), Vec3d(up)), ka = areaKernel(Vec3d(vertex), Vec3d(down), Vec3d(x), Vec3d(up));
  EXPECT_NEAR(e0.x, 2.0 * kp + 0.25 * ka, 1e-5 * (2.0 * kp + 0.25 * ka));
  EXPECT_NEAR(e0.z, 0.5 * kp + 1.0 * ka, 1e-5 * (0.5 * kp + 1.0 * ka));
  // The other side of the plane sees neither.
  EXPECT_EQ(t.sum(0, x, -up), Color(0.0f));
  EXPECT_EQ(t.sum(1, x, up), Color(0.0f));
  double expected = 0;
  for (int i = 0; i < 3; ++i) expected += pointKernel(Vec3d(0.1 * i, 0.5 + 0.2 * i, 0.3), Vec3d(x), Vec3d(up));
  EXPECT_NEAR(t.sum(2, x, up).y, expected, 1e-5 * expected);
}

TEST(NearTerms, SseSumIsThePortableSumBitForBit) {
  NearTerms t;
  t.clear();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int patch = 0; patch < 20; ++patch) {
    for (int i = 0; i < patch % 11; ++i) {
      const Vec3 p(u(rng), 1.0f + u(rng), u(rng)), c(u(rng) + 1.0f, u(rng) + 1.0f, u(rng) + 1.0f);
      if (i % 3 == 0)
        t.addPoint(p, c);
      else
        t.addArea(p, glm::normalize(Vec3(u(rng), -1.0f, u(rng))), c);
    }
    t.endPatch();
  }
  int nonZero = 0;
  for (int patch = 0; patch < 20; ++patch)
    for (int k = 0; k < 10; ++k) {
      const Vec3 x(u(rng), 0.2f * u(rng), u(rng)), n = glm::normalize(Vec3(0.3f * u(rng), 1.0f, 0.3f * u(rng)));
      const Color a = t.sum(patch, x, n), b = t.sumPortable(patch, x, n);
      EXPECT_EQ(a, b) << "patch " << patch;
      nonZero += a.x > 0.0f;
    }
  EXPECT_GT(nonZero, 100);
}
