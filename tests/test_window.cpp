// Windows around light samples: views and per-pixel weights (REFERENCE.md, "First-shot factors").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "common/lights/spot_cone.h"
#include "preprocess/window.h"

namespace firstshot {
namespace {

/// Σ weight · g(unit pixel direction in the local frame).
double integrate(const Window& w, const std::function<double(const Vec3d&)>& g) {
  double sum = 0;
  for (size_t f = 0; f < w.views.size(); ++f) {
    const View& v = w.views[f];
    for (int j = 0; j < v.height; ++j)
      for (int i = 0; i < v.width; ++i) {
        const double wt = w.weights[f][static_cast<size_t>(j) * v.width + i];
        if (wt != 0) sum += wt * g(glm::normalize(v.pixelDirection(i, j)));
      }
  }
  return sum;
}

void expectOrthonormal(const View& v) {
  EXPECT_NEAR(glm::length(v.right), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(v.up), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(v.forward), 1.0, 1e-12);
  EXPECT_NEAR(glm::dot(v.right, v.up), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(v.right, v.forward), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(v.up, v.forward), 0.0, 1e-12);
}

TEST(Window, CubeSumsTo4Pi) {
  const Window w = makeCubeWindow(512);
  ASSERT_EQ(w.views.size(), 6u);
  for (const View& v : w.views) expectOrthonormal(v);
  const double sum = w.totalWeight();
  std::printf("cube R=512: sum = %.9f, 4pi = %.9f, rel. error %.2e\n", sum, 4 * kPi, sum / (4 * kPi) - 1);
  EXPECT_NEAR(sum / (4 * kPi), 1.0, 1e-5);
  // The faces tile the sphere: ∫cos² = 4π/3 about any axis, first moments vanish.
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.z * d.z; }), 4 * kPi / 3, 1e-4);
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.x * d.x; }), 4 * kPi / 3, 1e-4);
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.x + 2 * d.y + 3 * d.z; }), 0.0, 1e-9);
}

TEST(Window, CubeCentreSamplingConvergesQuadratically) {
  // Centre sampling: error O(1/R²). (Corner sampling would be O(1/R).)
  const double e64 = std::abs(makeCubeWindow(64).totalWeight() / (4 * kPi) - 1);
  const double e128 = std::abs(makeCubeWindow(128).totalWeight() / (4 * kPi) - 1);
  EXPECT_GT(e64 / e128, 3.5);
  EXPECT_LT(e64 / e128, 4.5);
}

TEST(Window, HemicubeSumsToPi) {
  const Window w = makeHemicubeWindow(512);
  ASSERT_EQ(w.views.size(), 5u);
  EXPECT_EQ(w.views[0].width, 512);
  EXPECT_EQ(w.views[0].height, 512);
  for (size_t f = 1; f < 5; ++f) {
    EXPECT_EQ(w.views[f].width, 512);
    EXPECT_EQ(w.views[f].height, 256);
  }
  for (const View& v : w.views) {
    expectOrthonormal(v);
    // Every pixel looks into the upper hemisphere.
    for (int j = 0; j < v.height; ++j)
      for (int i = 0; i < v.width; ++i) ASSERT_GT(v.pixelDirection(i, j).z, 0.0);
  }
  const double sum = w.totalWeight();
  std::printf("hemicube R=512: sum = %.9f, pi = %.9f, rel. error %.2e\n", sum, kPi, sum / kPi - 1);
  EXPECT_NEAR(sum / kPi, 1.0, 1e-5);
  // Weight = cosθ dω: ∫cos² dω over the hemisphere = 2π/3; ∫ sinθ cosφ cosθ dω = 0.
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.z; }), 2 * kPi / 3, 1e-4);
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.x - d.y; }), 0.0, 1e-9);
  EXPECT_THROW(makeHemicubeWindow(511), std::invalid_argument);
}

TEST(Window, TetrahedronSumsToPi) {
  const Window w = makeTetraWindow(512);
  const int W = tetraFaceResolution(512);
  EXPECT_EQ(W, 724);
  ASSERT_EQ(w.views.size(), 3u);
  size_t valid = 0;
  for (size_t f = 0; f < 3; ++f) {
    const View& v = w.views[f];
    expectOrthonormal(v);
    EXPECT_EQ(v.width, W);
    EXPECT_EQ(v.height, W);
    for (int j = 0; j < W; ++j)
      for (int i = 0; i < W; ++i) {
        const double wt = w.weights[f][static_cast<size_t>(j) * W + i];
        const Vec3d d = v.pixelDirection(i, j);
        if (i < j) {
          ASSERT_EQ(wt, 0.0);  // below the base plane
        }
        if (i > j) {
          ASSERT_GT(wt, 0.0);
          ASSERT_GT(d.z, 0.0);
        }
        if (i == j) {
          ASSERT_NEAR(d.z, 0.0, 1e-12);  // boundary cells: centre on the base plane
        }
        valid += wt > 0;
      }
  }
  // Half of each face (the boundary cells are counted as valid too).
  EXPECT_EQ(valid, 3u * (static_cast<size_t>(W) * (W + 1) / 2));
  const double sum = w.totalWeight();
  std::printf("tetrahedron R=512 (faces %dx%d): sum = %.9f, pi = %.9f, rel. error %.2e\n", W, W, sum, kPi,
              sum / kPi - 1);
  EXPECT_NEAR(sum / kPi, 1.0, 1e-5);
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.z; }), 2 * kPi / 3, 1e-4);
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.x; }), 0.0, 1e-4);
  EXPECT_NEAR(integrate(w, [](const Vec3d& d) { return d.y; }), 0.0, 1e-4);
}

TEST(Window, TetrahedronBoundaryCells) {
  // The halved cells (i == j) carry the integral over their valid half, converged in the sub-grid
  // (16² against 128² sub-triangles), although the weight at their centre (on the base plane) is 0.
  const Window a = makeTetraWindow(32, 16), b = makeTetraWindow(32, 128);
  const int W = a.views[0].width;
  const double s = 3.0 / W;
  for (size_t f = 0; f < 3; ++f)
    for (int k = 0; k < W; ++k) {
      const size_t p = static_cast<size_t>(k) * W + k;
      EXPECT_NEAR(a.weights[f][p], b.weights[f][p], 1e-4 * b.weights[f][p]);
      // Between the bounds given by the density's extremes: (1+u+v) ≤ s over the half-cell, mean s/3.
      const Vec2d c = a.views[f].pixelCentre(k, k);
      const double r2 = 1 + c.x * c.x + c.y * c.y;
      const double approx = (s / 3) / (std::sqrt(3.0) * r2 * r2) * 0.5 * s * s;
      EXPECT_NEAR(b.weights[f][p], approx, 0.05 * approx);
    }
  // With the boundary handled, the sum converges like the midpoint rule: error O(1/W²).
  const double e64 = std::abs(makeTetraWindow(64).totalWeight() / kPi - 1);
  const double e128 = std::abs(makeTetraWindow(128).totalWeight() / kPi - 1);
  std::printf("tetrahedron sum error: R=64 %.2e, R=128 %.2e (ratio %.2f)\n", e64, e128, e64 / e128);
  EXPECT_GT(e64 / e128, 3.5);
  EXPECT_LT(e64 / e128, 4.5);
}

TEST(Window, OrthoCoversTheBounds) {
  Bounds3d b;
  b.extend({-1, 0, -2});
  b.extend({3, 2, 1});
  const Vec3d dir = glm::normalize(Vec3d(0.3, -1, 0.2));
  const Window w = makeOrthoWindow(256, b, dir);
  ASSERT_EQ(w.views.size(), 1u);
  const View& local = w.views[0];
  EXPECT_EQ(std::max(local.width, local.height), 256);
  const Framed frame(dir);
  const std::vector<View> placed = placeWindow(w, b.centre(), frame);
  const View& v = placed[0];
  EXPECT_NEAR(glm::dot(v.forward, dir), 1.0, 1e-12);
  for (int k = 0; k < 8; ++k) {
    const Vec3d d = b.corner(k) - v.eye;
    EXPECT_GT(glm::dot(d, v.forward), 0.0);  // in front of the eye
    const double u = glm::dot(d, v.right), s = glm::dot(d, v.up);
    EXPECT_GT(u, v.planeMin.x);
    EXPECT_LT(u, v.planeMax.x);
    EXPECT_GT(s, v.planeMin.y);
    EXPECT_LT(s, v.planeMax.y);
  }
  // Square pixels, weight = pixel area, total = the covered rectangle.
  const double px = (v.planeMax.x - v.planeMin.x) / v.width, py = (v.planeMax.y - v.planeMin.y) / v.height;
  EXPECT_NEAR(px, py, 1e-12 * px);
  EXPECT_DOUBLE_EQ(w.weights[0][0], px * py);
  EXPECT_NEAR(w.totalWeight(), (v.planeMax.x - v.planeMin.x) * (v.planeMax.y - v.planeMin.y), 1e-9);
}

TEST(Window, PlacementRotatesAndOffsets) {
  const Window w = makeHemicubeWindow(8);
  const Vec3d n = glm::normalize(Vec3d(0.2, -1, 0.1));
  const Framed frame(n);
  const Vec3d pos(1, 2, 3);
  const std::vector<View> views = placeWindow(w, pos, frame, 0.01);
  ASSERT_EQ(views.size(), 5u);
  for (const View& v : views) {
    expectOrthonormal(v);
    EXPECT_NEAR(glm::length(v.eye - (pos + 0.01 * n)), 0.0, 1e-15);
  }
  EXPECT_NEAR(glm::dot(views[0].forward, n), 1.0, 1e-12);  // top face looks along the normal
  for (size_t f = 1; f < 5; ++f) {
    EXPECT_NEAR(glm::dot(views[f].forward, n), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(views[f].up, n), 1.0, 1e-12);
  }
  // The same pixel direction, rotated: local z of a pixel equals its world component along n.
  const Vec3d local = w.views[2].pixelDirection(3, 1), world = views[2].pixelDirection(3, 1);
  EXPECT_NEAR(local.z, glm::dot(world, n), 1e-12);
  Bounds3d b;
  b.extend({0, 0, 0});
  b.extend({3, 4, 0});
  EXPECT_DOUBLE_EQ(areaLightEyeOffset(b), 5e-5);
}

TEST(Window, PixelOrder) {
  View v;
  v.width = 4;
  v.height = 2;
  v.planeMin = {-2, -1};
  v.planeMax = {2, 1};
  // Row 0 is the top (largest v), column 0 the left (smallest u).
  EXPECT_EQ(v.pixelCentre(0, 0), Vec2d(-1.5, 0.5));
  EXPECT_EQ(v.pixelCentre(3, 1), Vec2d(1.5, -0.5));
  EXPECT_EQ(v.pixelDirection(0, 0), Vec3d(-1.5, 0.5, 1));
}

}  // namespace
}  // namespace firstshot

namespace firstshot {

// A spot's cube window cropped to its cone: the pixels kept have the same centres and weights, the
// sum is unchanged, views outside the cone are dropped, and far fewer pixels remain to render.
TEST(Window, CropToWeightsKeepsEveryWeightedPixel) {
  const int R = 64;
  const Window cube = makeCubeWindow(R);
  Window spot = cube;
  SpotCone cone;
  cone.cosInner = std::cos(glm::radians(30.0)), cone.cosOuter = std::cos(glm::radians(50.0));
  for (size_t v = 0; v < spot.views.size(); ++v)
    for (int j = 0; j < R; ++j)
      for (int i = 0; i < R; ++i)
        spot.weights[v][size_t(j) * R + i] *= cone.profile(glm::normalize(spot.views[v].pixelDirection(i, j)).z);
  const double before = spot.totalWeight();
  Window cropped = spot;
  cropToWeights(cropped);
  EXPECT_EQ(cropped.totalWeight(), before);
  EXPECT_EQ(cropped.views.size(), 5u) << "the face opposite the axis holds no weight";
  EXPECT_LT(cropped.pixelCount() * 3, spot.pixelCount()) << cropped.pixelCount() << " of " << spot.pixelCount();
  // Every cropped pixel is an original pixel: same direction (to rounding) and the same weight.
  size_t matched = 0;
  for (const View& c : cropped.views) {
    const size_t cv = size_t(&c - cropped.views.data());
    const auto original = std::find_if(spot.views.begin(), spot.views.end(),
                                       [&](const View& o) { return o.forward == c.forward && o.up == c.up; });
    ASSERT_NE(original, spot.views.end());
    const size_t ov = size_t(original - spot.views.begin());
    const double du = (original->planeMax.x - original->planeMin.x) / R, dv = (original->planeMax.y - original->planeMin.y) / R;
    const int i0 = int(std::lround((c.planeMin.x - original->planeMin.x) / du));
    const int j0 = int(std::lround((original->planeMax.y - c.planeMax.y) / dv));
    for (int j = 0; j < c.height; ++j)
      for (int i = 0; i < c.width; ++i) {
        EXPECT_LT(glm::length(c.pixelDirection(i, j) - original->pixelDirection(i + i0, j + j0)), 1e-12);
        EXPECT_EQ(cropped.weights[cv][size_t(j) * c.width + i], spot.weights[ov][size_t(j + j0) * R + i + i0]);
        ++matched;
      }
  }
  EXPECT_EQ(matched, cropped.pixelCount());
}

}  // namespace firstshot
