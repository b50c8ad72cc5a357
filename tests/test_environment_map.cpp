// Environment maps and their sampling (common/sampling/distribution_2d.h, render/scene/environment_map.h): the map's density
// equals its luminance × sin θ over the normalisation, integrates to 1 over the sphere (Monte Carlo, 4σ), and
// sample() returns what pdf() says; texel frequencies pass a χ² test; a constant map is a furnace (irradiance π·L on
// any plane, 4σ); the mapping of directions to texels (zenith at the top row, −z at the centre) and the rotation.
#include <gtest/gtest.h>

#include <cmath>

#include "common/sampling/distribution_2d.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/util/error.h"
#include "render/scene/environment_map.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// A 16 × 8 map with a bright patch, some black texels and a gradient.
EnvironmentMap testMap(double rotationDeg = 0.0) {
  std::vector<Color> t(16 * 8);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 16; ++i) t[j * 16 + i] = Color(0.1f * float(i % 5), 0.2f, 0.05f * float(j));
  t[2 * 16 + 11] = Color(40.0f, 30.0f, 20.0f);
  t[5 * 16 + 3] = Color(0.0f);
  return EnvironmentMap(t, 16, 8, 2.0f, rotationDeg);
}

}  // namespace

TEST(EnvironmentMap, DensityIntegratesToOneAndMatchesSample) {
  const EnvironmentMap map = testMap(30.0);
  // ∫ pdf dω by uniform sphere sampling: mean of pdf / (1/4π).
  constexpr int n = 400000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    Sampler s(3, k, 0);
    const double v = map.pdf(squareToUniformSphere(s.next2D())) * 4.0 * kPi;
    sum += v, sum2 += v * v;
  }
  const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / (n - 1));
  EXPECT_NEAR(mean, 1.0, 4 * sigma) << "σ " << sigma;
  for (int k = 0; k < 2000; ++k) {
    Sampler s(5, k, 0);
    Vec3 dir;
    float pdf = 0;
    const Color l = map.sample(s.next2D(), dir, pdf);
    ASSERT_GT(pdf, 0.0f);
    EXPECT_NEAR(pdf, map.pdf(dir), 2e-3f * pdf) << k;
    EXPECT_EQ(l, map.radiance(dir)) << k;
  }
}

TEST(EnvironmentMap, TexelFrequenciesFollowLuminanceTimesSolidAngle) {
  const EnvironmentMap map = testMap();
  constexpr int n = 200000, w = 16, h = 8;
  std::vector<double> count(w * h, 0.0), expected(w * h, 0.0);
  double total = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double theta = kPi * (j + 0.5) / h, phi = 2 * kPi * ((i + 0.5) / w - 0.5);
      const Vec3 d(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)), float(-std::sin(theta) * std::cos(phi)));
      // luminance × the texel's exact solid angle (2π/w)(cos θ0 − cos θ1)
      const double omega = 2 * kPi / w * (std::cos(kPi * j / h) - std::cos(kPi * (j + 1) / h));
      expected[j * w + i] = map.pdf(d) > 0 ? (0.2126 * map.radiance(d).x + 0.7152 * map.radiance(d).y +
                                              0.0722 * map.radiance(d).z) * omega : 0.0;
      total += expected[j * w + i];
    }
  for (int k = 0; k < n; ++k) {
    Sampler s(11, k, 0);
    Vec3 dir;
    float pdf;
    map.sample(s.next2D(), dir, pdf);
    const double theta = std::acos(std::clamp(double(dir.y), -1.0, 1.0)), phi = std::atan2(double(dir.x), double(-dir.z));
    const int i = std::min(int((0.5 + phi / (2 * kPi)) * w), w - 1), j = std::min(int(theta / kPi * h), h - 1);
    count[j * w + i] += 1;
  }
  double chi2 = 0;
  int dof = -1;
  for (int c = 0; c < w * h; ++c) {
    const double e = expected[c] / total * n;
    if (e == 0) {
      EXPECT_EQ(count[c], 0) << "a black texel was drawn";
      continue;
    }
    chi2 += (count[c] - e) * (count[c] - e) / e;
    ++dof;
  }
  // The 1e-4 quantile of χ² with ~126 degrees of freedom is below dof + 4.5·sqrt(2·dof).
  EXPECT_LT(chi2, dof + 4.5 * std::sqrt(2.0 * dof)) << "dof " << dof;
}

TEST(EnvironmentMap, ConstantMapIsAFurnace) {
  const EnvironmentMap map(std::vector<Color>(32 * 16, Color(0.7f)), 32, 16);
  for (const Vec3 n : {Vec3(0, 1, 0), glm::normalize(Vec3(1, 0.3f, -0.5f))}) {
    constexpr int count = 100000;
    double sum = 0, sum2 = 0;
    for (int k = 0; k < count; ++k) {
      Sampler s(13, k, 0);
      Vec3 dir;
      float pdf;
      const Color l = map.sample(s.next2D(), dir, pdf);
      const double v = pdf > 0 ? l.x * std::max(0.0f, glm::dot(dir, n)) / pdf : 0.0;
      sum += v, sum2 += v * v;
    }
    const double mean = sum / count, sigma = std::sqrt((sum2 / count - mean * mean) / (count - 1));
    EXPECT_NEAR(mean, kPi * 0.7, 4 * sigma + 1e-9) << "σ " << sigma;
  }
}

TEST(EnvironmentMap, DirectionsToTexelsAndRotation) {
  std::vector<Color> t(8 * 4, Color(0.0f));
  t[0 * 8 + 3] = Color(1, 0, 0);  // top row: the zenith
  t[2 * 8 + 4] = Color(0, 1, 0);  // row 2 of 4: θ ∈ [90°, 135°), below the horizon
  t[1 * 8 + 4] = Color(0, 0, 1);  // row 1: θ ∈ [45°, 90°), column 4: φ ∈ [0, 45°) from −z towards +x
  const EnvironmentMap map(t, 8, 4);
  EXPECT_EQ(map.radiance(glm::normalize(Vec3(-0.01f, 1, -0.01f))), Color(1, 0, 0));
  EXPECT_EQ(map.radiance(glm::normalize(Vec3(0.2f, 0.3f, -1))), Color(0, 0, 1));
  EXPECT_EQ(map.radiance(glm::normalize(Vec3(0.2f, -0.3f, -1))), Color(0, 1, 0));
  // Rotated by 90° about y, the texel seen near −z is seen near −x instead.
  const EnvironmentMap rotated(t, 8, 4, 1.0f, 90.0);
  EXPECT_NE(rotated.radiance(glm::normalize(Vec3(0.2f, 0.3f, -1))), Color(0, 0, 1));
  EXPECT_EQ(rotated.radiance(glm::normalize(Vec3(-1, 0.3f, -0.2f))), Color(0, 0, 1));
}

TEST(EnvironmentMap, UnreadableFileNamesIt) {
  try {
    EnvironmentMap::load("/nonexistent/sky.exr");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/sky.exr"), std::string::npos) << e.what();
  }
}

// A Radiance .hdr map (read through OpenImageIO; PNG and EXR through render/output/image_io.h): 4 × 2 texels in flat
// RGBE (rows under 8 texels wide are never run-length encoded), the top row (2, 2, 2), the bottom (0.5, 0.25, 0.125):
// the zenith and the nadir get them back within the format's 8-bit mantissa (RGBE decoders differ by half a unit).
TEST(EnvironmentMap, ReadsRadianceHdr) {
  const std::string path = test::tempDir() + "/sky.hdr";
  std::string bytes = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
  for (int i = 0; i < 4; ++i) bytes += std::string{char(128), char(128), char(128), char(130)};  // 128·2^(130−136)
  for (int i = 0; i < 4; ++i) bytes += std::string{char(128), char(64), char(32), char(128)};    // 0.5, 0.25, 0.125
  test::writeText(path, bytes);
  const EnvironmentMap map = EnvironmentMap::load(path);
  const Color up = map.radiance(Vec3(0, 1, 0)), down = map.radiance(Vec3(0, -1, 0));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(up[c], 2.0f, 0.02f) << c;
  EXPECT_NEAR(down.x, 0.5f, 0.005f);
  EXPECT_NEAR(down.y, 0.25f, 0.005f);
  EXPECT_NEAR(down.z, 0.125f, 0.005f);
}

TEST(EnvironmentMap, UnreadableHdrNamesIt) {
  const std::string path = test::tempDir() + "/broken.hdr";
  test::writeText(path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n");  // no pixels
  try {
    EnvironmentMap::load(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.hdr"), std::string::npos) << e.what();
  }
}
