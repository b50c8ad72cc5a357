// Item buffers: OpenGL (OSMesa, EGL) and Embree back ends against analytic solid angles and each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <thread>

#include "preprocess/embree_item_buffer.h"
#include "preprocess/gl/gl_item_buffer.h"
#include "preprocess/window.h"

#if defined(__SANITIZE_ADDRESS__)
// Mesa's OSMesa never frees what OSMesaMakeCurrent allocates (see tests/lsan.supp); ours is all freed.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }
#endif

namespace firstshot {
namespace {

// ---------------------------------------------------------------------------------------------
// Meshes built by hand.

Patch makePatch(std::initializer_list<Vec3d> vertices) {
  Patch p;
  p.count = 0;
  for (const Vec3d& v : vertices) p.v[p.count++] = Vec3(v);
  computePatchGeometry(p);
  return p;
}

/// nu × nv grid of quads over the parallelogram o + [0,1]·eu + [0,1]·ev.
void addGrid(PatchMesh& mesh, const Vec3d& o, const Vec3d& eu, const Vec3d& ev, int nu, int nv) {
  for (int b = 0; b < nv; ++b)
    for (int a = 0; a < nu; ++a) {
      auto at = [&](int i, int k) { return o + (double(i) / nu) * eu + (double(k) / nv) * ev; };
      mesh.patches.push_back(makePatch({at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)}));
    }
}

/// Closed axis-aligned box [lo, hi] of n×n patches per face.
void addBox(PatchMesh& mesh, const Vec3d& lo, const Vec3d& hi, int n) {
  const Vec3d d = hi - lo;
  addGrid(mesh, lo, {d.x, 0, 0}, {0, d.y, 0}, n, n);
  addGrid(mesh, {lo.x, lo.y, hi.z}, {d.x, 0, 0}, {0, d.y, 0}, n, n);
  addGrid(mesh, lo, {0, d.y, 0}, {0, 0, d.z}, n, n);
  addGrid(mesh, {hi.x, lo.y, lo.z}, {0, d.y, 0}, {0, 0, d.z}, n, n);
  addGrid(mesh, lo, {d.x, 0, 0}, {0, 0, d.z}, n, n);
  addGrid(mesh, {lo.x, hi.y, lo.z}, {d.x, 0, 0}, {0, 0, d.z}, n, n);
}

Bounds3d boundsOf(const ItemGeometry& g) { return g.bounds; }

/// Solid angle of a planar polygon seen from @p eye (Van Oosterom–Strackee, fan sum; REFERENCE.md).
double solidAngle(const Patch& p, const Vec3d& eye) {
  const Vec3d r0 = Vec3d(p.v[0]) - eye;
  double total = 0;
  for (uint32_t k = 1; k + 1 < p.count; ++k) {
    const Vec3d r1 = Vec3d(p.v[k]) - eye, r2 = Vec3d(p.v[k + 1]) - eye;
    const double l0 = glm::length(r0), l1 = glm::length(r1), l2 = glm::length(r2);
    const double num = glm::dot(r0, glm::cross(r1, r2));
    const double den = l0 * l1 * l2 + glm::dot(r0, r1) * l2 + glm::dot(r0, r2) * l1 + glm::dot(r1, r2) * l0;
    total += 2 * std::atan2(num, den);
  }
  return std::abs(total);
}

// ---------------------------------------------------------------------------------------------
// Back ends.

const char* kBackends[] = {"osmesa", "egl", "embree"};

/// Creates a renderer; on failure returns null and sets @p why (EGL may be unavailable).
std::unique_ptr<ItemBufferRenderer> makeRenderer(const std::string& backend, const ItemGeometry& g,
                                                 const Bounds3d& bounds, std::string& why) {
  try {
    if (backend == "embree") return std::make_unique<EmbreeItemBuffer>(g, bounds);
    return std::make_unique<GLItemBuffer>(g, bounds, parseGLBackend(backend));
  } catch (const std::exception& e) {
    why = e.what();
    return nullptr;
  }
}

#define MAKE_RENDERER_OR_SKIP(var, backend, geometry, bounds)                                        \
  std::string var##Why;                                                                            \
  auto var = makeRenderer(backend, geometry, bounds, var##Why);                                    \
  if (!var) {                                                                                      \
    if (std::string(backend) == "egl") {                                                           \
      GTEST_SKIP() << "EGL unavailable here: " << var##Why;                                        \
    }                                                                                              \
    FAIL() << var##Why;                                                                            \
  }

/// Per-patch Σ weight and pixel count over all views of a window.
struct Accum {
  std::vector<double> weight;
  std::vector<uint64_t> pixels;
  uint64_t foreign = 0;  ///< pixels with an ID outside [0, n) other than kNoPatch
};

Accum accumulate(ItemBufferRenderer& r, const std::vector<View>& views, const Window& w, uint32_t n,
                 std::vector<std::vector<uint32_t>>* buffers = nullptr) {
  Accum a{std::vector<double>(n, 0.0), std::vector<uint64_t>(n, 0), 0};
  std::vector<uint32_t> ids;
  for (size_t f = 0; f < views.size(); ++f) {
    r.render(views[f], ids);
    EXPECT_EQ(ids.size(), views[f].pixelCount());
    for (size_t p = 0; p < ids.size(); ++p) {
      if (ids[p] == kNoPatch) continue;
      if (ids[p] >= n) {
        ++a.foreign;
        continue;
      }
      a.weight[ids[p]] += w.weights[f][p];
      a.pixels[ids[p]] += 1;
    }
    if (buffers) buffers->push_back(ids);
  }
  return a;
}

class ItemBuffer : public ::testing::TestWithParam<const char*> {};

/// Weight of the pixels on the boundary of each patch's region, B_j: a pixel counts for every ID seen in
/// its 3×3 neighbourhood when that neighbourhood is not uniform; pixels on the image border count for
/// their own ID. @p outline collects the pixels where patches meet the background. Centre sampling
/// misassigns only such pixels (for regions at least ~2 pixels wide), so |Σδω_j − Ω_j| ≤ B_j.
void boundaryWeights(const std::vector<uint32_t>& ids, const View& v, const std::vector<double>& w,
                     std::vector<double>& perPatch, double& outline) {
  const int W = v.width, H = v.height;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const size_t p = static_cast<size_t>(j) * W + i;
      uint32_t seen[9];
      int n = 0;
      seen[n++] = ids[p];
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (i + di < 0 || j + dj < 0 || i + di >= W || j + dj >= H) continue;
          const uint32_t q = ids[static_cast<size_t>(j + dj) * W + i + di];
          if (std::find(seen, seen + n, q) == seen + n) seen[n++] = q;
        }
      const bool border = i == 0 || j == 0 || i == W - 1 || j == H - 1;
      if (n == 1 && !border) continue;
      bool background = false;
      for (int k = 0; k < n; ++k) {
        if (seen[k] == kNoPatch)
          background = true;
        else
          perPatch[seen[k]] += w[p];
      }
      if (background && n > 1) outline += w[p];
    }
}

// ---------------------------------------------------------------------------------------------
// Point light over a plane of square patches: r_ij = Σ δω / (4π A_j) against Ω_j / (4π A_j).

TEST_P(ItemBuffer, PointLightOverPlaneMatchesSolidAngles) {
  PatchMesh mesh;
  addGrid(mesh, {-3, -3, 0}, {6, 0, 0}, {0, 6, 0}, 60, 60);  // 0.1 m patches
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, boundsOf(g));
  const Vec3d light(0.0123, -0.0271, 0.5);
  const int R = 512;
  const Window cube = makeCubeWindow(R);
  const auto views = placeWindow(cube, light, Framed(Vec3d(0, 0, 1)));
  std::vector<std::vector<uint32_t>> buffers;
  const Accum a = accumulate(*r, views, cube, mesh.size(), &buffers);
  EXPECT_EQ(a.foreign, 0u);
  std::vector<double> bound(mesh.size(), 0.0);
  double outline = 0;
  for (size_t f = 0; f < views.size(); ++f) boundaryWeights(buffers[f], views[f], cube.weights[f], bound, outline);

  // Error of r_ij (= relative error of Ω_j) against the patch width in pixels k = √(Ω_j / δω_pixel),
  // with δω_pixel = 4 cos³θ / R² of a pixel in the patch's direction (expected, not measured: binning by
  // the measured pixel count would bias the mean error of each bin).
  auto expectedWidth = [&](uint32_t j) {
    const Vec3d d = glm::normalize(Vec3d(mesh.patches[j].centroid) - light);
    const double c = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});  // cos θ on the face seeing it
    return std::sqrt(solidAngle(mesh.patches[j], light) / (4 * c * c * c / (double(R) * R)));
  };
  const double edges[] = {0, 3, 5, 7, 10, 14, 20, 30, 1e9};
  const int nBins = 8;
  double maxErr[nBins] = {0}, sumSq[nBins] = {0}, sum[nBins] = {0};
  int count[nBins] = {0};
  double omegaSum = 0, estSum = 0;
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const double omega = solidAngle(mesh.patches[j], light);
    const double rExact = omega / (4 * kPi * mesh.patches[j].area);
    const double rEst = a.weight[j] / (4 * kPi * mesh.patches[j].area);
    omegaSum += omega;
    estSum += a.weight[j];
    const double err = rEst / rExact - 1;
    const double k = expectedWidth(j);
    int b = 0;
    while (k >= edges[b + 1]) ++b;
    maxErr[b] = std::max(maxErr[b], std::abs(err));
    sumSq[b] += err * err;
    sum[b] += err;
    ++count[b];
    // Every patch is seen, and only its boundary pixels are wrong (plus the O(1/R²) quadrature error).
    ASSERT_GT(a.pixels[j], 0u) << "patch " << j;
    EXPECT_LE(std::abs(a.weight[j] - omega), bound[j] + 1e-4 * omega) << "patch " << j << " k = " << k;
  }
  std::printf("%s, point light 0.5 m over 60x60 patches of 0.1 m, cube R = %d:\n"
              "  k (pixels)        patches  max |err|  RMS err  mean err (± 3 s.e.)\n", r->name(), R);
  for (int b = 0; b < nBins; ++b) {
    if (count[b] == 0) continue;
    const double rms = std::sqrt(sumSq[b] / count[b]), mean = sum[b] / count[b];
    const double se = std::sqrt(std::max(0.0, sumSq[b] / count[b] - mean * mean) / count[b]);
    std::printf("  [%4.0f,%4.0f)      %7d   %7.3f%%  %6.3f%%  %+7.3f%% (± %.3f%%)\n", edges[b],
                std::min(edges[b + 1], 999.0), count[b], 100 * maxErr[b], 100 * rms, 100 * mean, 300 * se);
    // (The mean is printed only: neighbouring patches' errors are correlated, so ± 3 s.e. is no bound.)
    // Aliasing shrinks like 1/k (REFERENCE: RMS ≈ 0.55/k for squares facing the eye; these are
    // often seen obliquely, hence elongated, so allow 1/k).
    if (edges[b] >= 3) {
      EXPECT_LT(rms, 1.0 / edges[b]) << "bin " << edges[b];
    }
  }
  // Internal edges cancel: the whole plane is wrong only by its outline pixels.
  std::printf("  whole plane: sum of δω %.6f, analytic %.6f (%.2e); outline pixels weigh %.6f\n", estSum, omegaSum,
              estSum / omegaSum - 1, outline);
  EXPECT_LE(std::abs(estSum - omegaSum), 0.5 * outline);
}

// ---------------------------------------------------------------------------------------------
// Pixel order: row 0 at the top of the view, column 0 at the left.

TEST_P(ItemBuffer, PixelOrderIsRowMajorFromTheTop) {
  PatchMesh mesh;
  // Seen from the origin looking along +z with right = +x, up = +y: a patch in the upper-left quadrant.
  mesh.patches.push_back(makePatch({{-0.88, 0.12, 1}, {-0.12, 0.12, 1}, {-0.12, 0.88, 1}, {-0.88, 0.88, 1}}));
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, boundsOf(g));
  View v;
  v.width = 20;
  v.height = 10;
  std::vector<uint32_t> ids;
  r->render(v, ids);
  ASSERT_EQ(ids.size(), 200u);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 20; ++i) {
      const Vec2d c = v.pixelCentre(i, j);
      const bool inside = c.x > -0.88 && c.x < -0.12 && c.y > 0.12 && c.y < 0.88;
      EXPECT_EQ(ids[j * 20 + i], inside ? 0u : kNoPatch) << "pixel " << i << "," << j;
    }
  EXPECT_EQ(ids[1 * 20 + 2], 0u);  // near the top-left corner
}

// ---------------------------------------------------------------------------------------------
// Hard cases.

TEST_P(ItemBuffer, PatchVeryCloseToTheEye) {
  // A 1e-4 m square 1e-4 m in front of an eye at non-representable coordinates, in a 10 m scene.
  const Vec3d eye(1.3, 0.7, 2.1);
  const double s = 1e-4;
  PatchMesh mesh;
  mesh.patches.push_back(makePatch({eye + Vec3d(-s / 2, -s / 2, s), eye + Vec3d(s / 2, -s / 2, s),
                                    eye + Vec3d(s / 2, s / 2, s), eye + Vec3d(-s / 2, s / 2, s)}));
  addGrid(mesh, {-4, -4, 6}, {8, 0, 0}, {0, 8, 0}, 4, 4);  // a far wall behind it
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  const Bounds3d bounds = g.bounds;
  ASSERT_GT(bounds.diagonal(), 10.0);
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, bounds);
  ASSERT_LT(r->nearPlane(), 0.2 * s);
  const Window cube = makeCubeWindow(512);
  const Accum a = accumulate(*r, placeWindow(cube, eye, Framed(Vec3d(0, 0, 1))), cube, mesh.size());
  const double omega = solidAngle(mesh.patches[0], eye);  // from the stored float vertices
  std::printf("%s: 1e-4 m patch at 1e-4 m: sum of δω %.6f, analytic %.6f (%.2e), %llu pixels\n", r->name(),
              a.weight[0], omega, a.weight[0] / omega - 1, static_cast<unsigned long long>(a.pixels[0]));
  EXPECT_NEAR(omega, 0.8054317, 0.01);  // about a unit square at distance 1
  EXPECT_NEAR(a.weight[0] / omega, 1.0, 5e-3);
}

TEST_P(ItemBuffer, NearPlaneIsADepthAlongForward) {
  // Both back ends clip at depth near (= 1e-6 × diagonal) measured along the view direction.
  PatchMesh mesh;
  mesh.patches.push_back(makePatch({{-5, -5, 5}, {5, -5, 5}, {5, 5, 5}, {-5, 5, 5}}));  // far wall, id 0
  const ItemGeometry g0 = ItemGeometry::fromPatches(mesh);
  const double near = itemBufferNear(g0.bounds);
  auto square = [&](double z, double half) {
    return makePatch({{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}});
  };
  mesh.patches.push_back(square(0.5 * near, 4 * near));  // id 1: before the near plane, covers the view
  mesh.patches.push_back(square(0.5 * near, 4 * near));  // (twice, to be sure it is not a fluke)
  mesh.patches.push_back(square(2.0 * near, 0.5 * near)); // id 3: behind it, covers |u|, |v| < 0.25
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, g.bounds);
  EXPECT_DOUBLE_EQ(r->nearPlane(), itemBufferNear(g.bounds));
  View v;
  v.width = v.height = 16;
  std::vector<uint32_t> ids;
  r->render(v, ids);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      const Vec2d c = v.pixelCentre(i, j);
      const bool centre = std::abs(c.x) < 0.25 && std::abs(c.y) < 0.25;
      EXPECT_EQ(ids[j * 16 + i], centre ? 3u : 0u) << i << "," << j;
    }
}

TEST_P(ItemBuffer, EdgeOnPatchNeitherShowsNorLeaks) {
  // A patch in the plane x = 0 through the eye, in front of a square: it must not cover any pixel,
  // nor open a crack in the square behind it. Its projection, u = 0, lies on pixel boundaries.
  PatchMesh mesh;
  mesh.patches.push_back(makePatch({{-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}}));
  mesh.patches.push_back(makePatch({{0, -0.5, 0.5}, {0, 0.5, 0.5}, {0, 0.5, 1.5}, {0, -0.5, 1.5}}));
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, boundsOf(g));
  const Window cube = makeCubeWindow(256);
  const Vec3d eye(0, 0, 0);
  const Accum a = accumulate(*r, placeWindow(cube, eye, Framed(Vec3d(0, 0, 1))), cube, mesh.size());
  EXPECT_EQ(a.pixels[1], 0u);
  const double omega = solidAngle(mesh.patches[0], eye);
  EXPECT_NEAR(omega, 4 * std::atan(4.0 / (4 * std::sqrt(16.0 + 8.0))), 1e-6);
  EXPECT_NEAR(a.weight[0] / omega, 1.0, 2e-3);
  // Exactly the pixels whose centres fall inside the square's projection (|u|, |v| < 0.5 on face +z).
  const View front = placeWindow(cube, eye, Framed(Vec3d(0, 0, 1)))[4];
  ASSERT_NEAR(front.forward.z, 1.0, 1e-12);
  EXPECT_EQ(a.pixels[0], 128u * 128u);
}

TEST_P(ItemBuffer, PatchIdsAbove2To24ComeBackExactly) {
  // IDs that a float could not carry: 2^24 + 1 is not representable in binary32.
  const uint32_t idsWanted[] = {16777217u, 16777219u, 0x7FFFFFFFu, 0xFFFFFFFEu, 0u, 123456789u};
  ItemGeometry g;
  for (int k = 0; k < 6; ++k) {  // six small squares in a row at z = 1
    const float x0 = -0.9f + 0.3f * k;
    g.addTriangle({x0, -0.1f, 1}, {x0 + 0.2f, -0.1f, 1}, {x0 + 0.2f, 0.1f, 1}, idsWanted[k]);
    g.addTriangle({x0, -0.1f, 1}, {x0 + 0.2f, 0.1f, 1}, {x0, 0.1f, 1}, idsWanted[k]);
  }
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, g.bounds);
  View v;
  v.width = v.height = 64;
  std::vector<uint32_t> ids;
  r->render(v, ids);
  std::map<uint32_t, int> seen;
  for (uint32_t id : ids) seen[id]++;
  ASSERT_EQ(seen.size(), 7u);  // six patches and the background
  for (uint32_t want : idsWanted) EXPECT_GT(seen[want], 30) << want;
  EXPECT_GT(seen[kNoPatch], 0);
}

TEST_P(ItemBuffer, AreaLightVertexDoesNotSeeItsOwnPlane) {
  // A ceiling of patches at z = 1 with the light vertex on it, normal -z: the ceiling itself lies on the
  // hemicube's base plane and must get nothing; the floor gets its full form factor.
  PatchMesh mesh;
  addGrid(mesh, {-2, -2, 1}, {4, 0, 0}, {0, 4, 0}, 8, 8);  // ceiling (patches 0..63)
  addGrid(mesh, {-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, 8, 8);  // floor (64..127)
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  MAKE_RENDERER_OR_SKIP(r, GetParam(), g, g.bounds);
  const Vec3d vertex(0.25, 0.5, 1.0);  // on a ceiling patch corner
  const Window hemi = makeHemicubeWindow(256);
  const auto views = placeWindow(hemi, vertex, Framed(Vec3d(0, 0, -1)), areaLightEyeOffset(g.bounds));
  const Accum a = accumulate(*r, views, hemi, mesh.size());
  double ceiling = 0, floor = 0;
  for (uint32_t j = 0; j < 64; ++j) ceiling += a.weight[j];
  for (uint32_t j = 64; j < 128; ++j) floor += a.weight[j];
  EXPECT_EQ(ceiling, 0.0);
  // Point-to-polygon form factor of the 4×4 floor at distance 1 (REFERENCE.md, Lambert formula).
  const Vec3d c[4] = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
  double F = 0;
  const Vec3d n(0, 0, -1);
  for (int i = 0; i < 4; ++i) {
    const Vec3d ri = c[i] - vertex, rj = c[(i + 1) % 4] - vertex;
    const Vec3d x = glm::cross(ri, rj);
    F += std::acos(glm::dot(ri, rj) / (glm::length(ri) * glm::length(rj))) * glm::dot(n, x) / glm::length(x);
  }
  F = std::abs(F) / (2 * kPi);
  EXPECT_NEAR(floor / kPi, F, 2e-3 * F);
}

// ---------------------------------------------------------------------------------------------
// GL against Embree on a box with blocks: identical up to pixels on patch edges.

PatchMesh makeRoom() {
  PatchMesh mesh;
  // Open-front room 2×2×2 with two blocks inside.
  addGrid(mesh, {0, 0, 0}, {2, 0, 0}, {0, 0, 2}, 20, 20);  // floor y = 0
  addGrid(mesh, {0, 2, 0}, {2, 0, 0}, {0, 0, 2}, 20, 20);  // ceiling
  addGrid(mesh, {0, 0, 2}, {2, 0, 0}, {0, 2, 0}, 20, 20);  // back
  addGrid(mesh, {0, 0, 0}, {0, 2, 0}, {0, 0, 2}, 20, 20);  // left
  addGrid(mesh, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, 20, 20);  // right
  addBox(mesh, {0.3, 0, 0.9}, {0.8, 0.6, 1.4}, 6);
  addBox(mesh, {1.1, 0, 0.4}, {1.6, 1.2, 0.9}, 8);
  return mesh;
}

TEST(ItemBufferAgreement, GLAndEmbreeDifferOnlyOnPatchEdges) {
  const PatchMesh mesh = makeRoom();
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  GLItemBuffer gl(g, g.bounds);
  EmbreeItemBuffer em(g, g.bounds);
  struct Case {
    const char* name;
    Window window;
    std::vector<View> views;
  };
  std::vector<Case> cases;
  {
    Window w = makeCubeWindow(256);
    auto v = placeWindow(w, {0.93, 1.37, 0.61}, Framed(glm::normalize(Vec3d(0.1, 1, 0.2))));
    cases.push_back({"cube", std::move(w), std::move(v)});
  }
  {
    Window w = makeHemicubeWindow(256);
    auto v = placeWindow(w, {1.03, 2.0, 1.11}, Framed(Vec3d(0, -1, 0)), areaLightEyeOffset(g.bounds));
    cases.push_back({"hemicube", std::move(w), std::move(v)});
  }
  {
    Window w = makeTetraWindow(192);
    auto v = placeWindow(w, {1.03, 2.0, 1.11}, Framed(Vec3d(0, -1, 0)), areaLightEyeOffset(g.bounds));
    cases.push_back({"tetrahedron", std::move(w), std::move(v)});
  }
  {
    const Vec3d dir = glm::normalize(Vec3d(0.3, -1, 0.4));
    Window w = makeOrthoWindow(256, g.bounds, dir);
    auto v = placeWindow(w, g.bounds.centre(), Framed(dir));
    cases.push_back({"ortho", std::move(w), std::move(v)});
  }
  for (const Case& c : cases) {
    std::vector<std::vector<uint32_t>> bg, be;
    const Accum ag = accumulate(gl, c.views, c.window, mesh.size(), &bg);
    const Accum ae = accumulate(em, c.views, c.window, mesh.size(), &be);
    size_t differing = 0, total = 0;
    std::vector<double> edgeWeight(mesh.size(), 0.0);
    for (size_t f = 0; f < c.views.size(); ++f) {
      const int W = c.views[f].width, H = c.views[f].height;
      auto at = [&](const std::vector<uint32_t>& b, int i, int j) {
        return (i < 0 || j < 0 || i >= W || j >= H) ? kNoPatch - 1 : b[static_cast<size_t>(j) * W + i];
      };
      for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
          const size_t p = static_cast<size_t>(j) * W + i;
          ++total;
          // Edge pixels: the 3×3 neighbourhood is not uniform in one of the buffers. They count for
          // the patches either buffer shows there.
          bool edge = false;
          for (const auto* b : {&bg[f], &be[f]})
            for (int dj = -1; dj <= 1; ++dj)
              for (int di = -1; di <= 1; ++di) {
                const uint32_t q = at(*b, i + di, j + dj);
                edge |= q != (*b)[p] && q != kNoPatch - 1;
              }
          if (edge) {
            if (bg[f][p] != kNoPatch) edgeWeight[bg[f][p]] += c.window.weights[f][p];
            if (be[f][p] != kNoPatch && be[f][p] != bg[f][p]) edgeWeight[be[f][p]] += c.window.weights[f][p];
          }
          const uint32_t idG = bg[f][p], idE = be[f][p];
          if (idG == idE) continue;
          ++differing;
          // A tie: the other back end's ID is right next to this pixel.
          bool tie = false;
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di)
              tie |= at(bg[f], i + di, j + dj) == idE || at(be[f], i + di, j + dj) == idG;
          EXPECT_TRUE(tie) << c.name << " view " << f << " pixel " << i << "," << j << ": gl " << idG
                           << " embree " << idE;
        }
    }
    std::printf("%s: %zu of %zu pixels differ (%.4f%%)\n", c.name, differing, total, 100.0 * differing / total);
    EXPECT_LT(double(differing), 2e-3 * double(total)) << c.name;
    for (uint32_t j = 0; j < mesh.size(); ++j)
      EXPECT_LE(std::abs(ag.weight[j] - ae.weight[j]), edgeWeight[j] + 1e-15) << c.name << " patch " << j;
  }
}

// ---------------------------------------------------------------------------------------------
// Threads: one context per worker, all giving the same buffers.

TEST(ItemBufferThreads, ContextsInSeveralThreadsAgree) {
  const PatchMesh mesh = makeRoom();
  const ItemGeometry g = ItemGeometry::fromPatches(mesh);
  const Window w = makeCubeWindow(96);
  const auto views = placeWindow(w, {0.93, 1.37, 0.61}, Framed(Vec3d(0, 1, 0)));
  std::vector<std::vector<uint32_t>> reference;
  {
    GLItemBuffer gl(g, g.bounds);
    std::vector<uint32_t> ids;
    for (const View& v : views) {
      gl.render(v, ids);
      reference.push_back(ids);
    }
  }
  bool eglAvailable = true;
  try {
    GLContext probe(GLBackend::EGL);
  } catch (const std::exception&) {
    eglAvailable = false;  // the third worker then uses OSMesa too (EglSurfacelessWorks reports the skip)
  }
  std::vector<std::string> errors(3);
  std::vector<int> mismatches(3, 0);
  auto worker = [&](int t) {
    try {
      GLItemBuffer gl(g, g.bounds, t == 2 && eglAvailable ? GLBackend::EGL : GLBackend::OSMesa);
      std::vector<uint32_t> ids;
      for (int rep = 0; rep < 3; ++rep)
        for (size_t f = 0; f < views.size(); ++f) {
          gl.render(views[f], ids);
          mismatches[t] += ids != reference[f];
        }
    } catch (const std::exception& e) {
      errors[t] = e.what();
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < 3; ++t) threads.emplace_back(worker, t);
  for (auto& th : threads) th.join();
  for (int t = 0; t < 3; ++t) {
    EXPECT_EQ(errors[t], "") << "thread " << t;
    EXPECT_EQ(mismatches[t], 0) << "thread " << t;
  }
}

TEST(GLContextTest, DescribesItselfAndRejectsUnknownBackends) {
  GLContext ctx(GLBackend::OSMesa);
  const std::string d = ctx.description();
  std::printf("OSMesa: %s\n", d.c_str());
  EXPECT_NE(d.find("4.5"), std::string::npos);
  EXPECT_THROW(parseGLBackend("vulkan"), std::invalid_argument);
  EXPECT_EQ(parseGLBackend("egl"), GLBackend::EGL);
}

TEST(GLContextTest, EglSurfacelessWorks) {
  try {
    GLContext ctx(GLBackend::EGL);
    std::printf("EGL: %s\n", ctx.description().c_str());
  } catch (const std::exception& e) {
    GTEST_SKIP() << "EGL unavailable here: " << e.what();
  }
}

TEST(GLContextDeathTest, UnavailableBackendIsAClearError) {
  // A fresh process in which glvnd finds no EGL vendor: the error names the back end.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json", 1);
        try {
          GLContext ctx(GLBackend::EGL);
          std::fprintf(stderr, "unexpectedly created\n");
          std::exit(1);
        } catch (const std::runtime_error& e) {
          std::fprintf(stderr, "%s\n", e.what());
          std::exit(0);
        }
      },
      ::testing::ExitedWithCode(0), "OpenGL back end 'egl': ");
}

INSTANTIATE_TEST_SUITE_P(Backends, ItemBuffer, ::testing::ValuesIn(kBackends),
                         [](const auto& param) { return std::string(param.param); });

}  // namespace
}  // namespace firstshot
