// The variance report (bench/variance_report.h, firstshot-variance): its categories partition every camera sample's
// radiance, so their means add up to the path tracer's image with the same seed; a category is where the light's
// path puts it (direct light by NEE at bounce 1, no length past --max-depth, caustics only through glass), and the
// same direct light in another category (with and without a table) has the same mean within 3σ.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include "bench/variance_report.h"
#include "tests/render_util.h"
#include "tests/shaded_room.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

VarianceReport reportOf(const RenderScene& scene, const IntegratorOptions& io, int spp, uint64_t seed, int threads = 0) {
  auto path = makeIntegrator("path", io);
  path->preprocess(scene);
  VarianceReportOptions o;
  o.spp = spp;
  o.seed = seed;
  o.threads = threads;
  return varianceReport(*path, scene, o);
}

/// The category (bounces, term, via) of @p r, or one that added nothing.
VarianceCategory find(const VarianceReport& r, int bounces, PathTerm term, PathVia via) {
  for (const VarianceCategory& c : r.categories)
    if (c.bounces == bounces && c.term == int(term) && c.via == int(via)) return c;
  return VarianceCategory{bounces, int(term), int(via)};
}

/// A category's image mean: its mean over the pixels.
double imageMean(const VarianceReport& r, const VarianceCategory& c) { return c.meanSum / (double(r.width) * r.height); }

/// Standard error of a category's image mean, from its per-pixel sample variances.
double imageSe(const VarianceReport& r, const VarianceCategory& c) {
  const double pixels = double(r.width) * double(r.height);
  return std::sqrt(c.varianceSum / double(r.spp)) / pixels;
}

double sumOfMeans(const std::vector<VarianceCategory>& cats) {
  double s = 0;
  for (const VarianceCategory& c : cats) s += c.meanSum;
  return s;
}

/// A 2 m box lit by a small emissive sphere under its ceiling, above a ball of @p ball's material.
SceneDesc ballBox(const std::string& ball) {
  return test::sceneFromJson(R"({
  "materials": {"wall": {"type": "diffuse", "albedo": 0.6}, "ball": )" + ball + R"(,
                "lamp": {"type": "diffuse", "emission": 40}},
  "shapes": [
    {"type": "box", "min": [0, 0, 0], "max": [2, 2, 2], "material": "wall", "flip_normals": true},
    {"type": "sphere", "material": "ball", "center": [1, 0.8, 1], "radius": 0.35, "subdivisions": 3, "smooth": true},
    {"type": "sphere", "material": "lamp", "center": [1, 1.75, 1], "radius": 0.12, "subdivisions": 2}],
  "camera": {"position": [1, 1.5, 1.95], "look_at": [1, 0.2, 0.9], "fov_y": 70, "resolution": [16, 16]},
  "settings": {"max_depth": 6}
})");
}

}  // namespace

// The categories partition each sample's L: their means add up to the image mean, which is the path integrator's
// image with the same seed (the renderer's samplers and camera rays); with and without a table and patch NEE.
TEST(VarianceReport, CategoriesAddUpToThePathImage) {
  const SceneDesc desc = test::shadedLightRoom(12);
  const RenderScene plain(desc, desc.settings.patchSize);
  const RenderScene table(desc, test::quickTable(desc));
  const int spp = 6;
  const uint64_t seed = 5;
  for (const auto& [scene, nee, what] : {std::tuple{&plain, PatchNee::Off, "no table"},
                                         std::tuple{&table, PatchNee::Off, "table"},
                                         std::tuple{&table, PatchNee::Every, "table, patch NEE"}}) {
    IntegratorOptions io;
    io.patchNee = nee;
    const VarianceReport r = reportOf(*scene, io, spp, seed);
    const double pixels = double(r.width) * double(r.height);
    const double image = test::greyImageMean(test::renderPath(*scene, io, spp, seed).film);
    fmt::print("  {}: image {:.6g}, report {:.6g}, categories {:.6g}, partition error {:.1e}\n", what, image,
               r.imageMean(), sumOfMeans(r.categories) / pixels, r.partitionError);
    ASSERT_GT(image, 0.0) << what;
    EXPECT_EQ(r.nonFinite, 0u) << what;
    EXPECT_NEAR(r.imageMean(), image, 1e-5 * image) << what;
    EXPECT_NEAR(sumOfMeans(r.categories), r.image.meanSum, 1e-5 * r.image.meanSum) << what;
    EXPECT_NEAR(sumOfMeans(r.byTerm), r.image.meanSum, 1e-5 * r.image.meanSum) << what;
    EXPECT_NEAR(sumOfMeans(r.byBounces), r.image.meanSum, 1e-5 * r.image.meanSum) << what;
    EXPECT_LT(r.partitionError, 1e-5) << what;
    // Variances of parts add up to less than the whole's only through covariances, which are ≥ 0 here (every part
    // of a path's light grows with the same throughput); and the sum of parts is never above the total by more
    // than rounding.
    EXPECT_LE(r.categoryVarianceSum, r.image.varianceSum * (1 + 1e-9)) << what;
    EXPECT_GT(r.categoryVarianceSum, 0.0) << what;
  }
}

// The report is the same for any number of threads (rows summed in order).
TEST(VarianceReport, SameForOneAndTwoThreads) {
  const SceneDesc desc = test::shadedLightRoom(12);
  const RenderScene scene(desc, test::quickTable(desc));
  IntegratorOptions io;
  io.patchNee = PatchNee::Every;
  const VarianceReport one = reportOf(scene, io, 4, 3, 1), two = reportOf(scene, io, 4, 3, 2);
  EXPECT_EQ(one.image.meanSum, two.image.meanSum);
  EXPECT_EQ(one.image.varianceSum, two.image.varianceSum);
  ASSERT_EQ(one.categories.size(), two.categories.size());
  for (size_t k = 0; k < one.categories.size(); ++k)
    EXPECT_EQ(one.categories[k].varianceSum, two.categories[k].varianceSum) << one.categories[k].name(8);
}

// Where the direct light goes: the point light is replaced by the table, and the path tracer takes it exactly by NEE
// at camera-visible points (PrimaryMode::Exact), as a kept light does without a table. So with the table, bounce 1
// holds small-light NEE and no table term (the table serves bounces 2 on), and without it bounce 1 holds large-light
// NEE and no small light at all; both direct terms have the same mean within 3σ. Patch NEE at vertex k is light of
// length k + 2: none at bounce 1.
TEST(VarianceReport, DirectLightByNeeWithAndWithoutTable) {
  const SceneDesc desc = test::shadedLightRoom(12);
  const RenderScene plain(desc, desc.settings.patchSize);
  const RenderScene table(desc, test::quickTable(desc));
  IntegratorOptions io;
  io.patchNee = PatchNee::Every;
  const int spp = 16;
  const VarianceReport a = reportOf(table, io, spp, 1), b = reportOf(plain, io, spp, 2);
  const VarianceCategory small = find(a, 1, PathTerm::SmallLightNee, PathVia::Direct);
  const VarianceCategory kept = find(b, 1, PathTerm::LargeLightNee, PathVia::Direct);
  EXPECT_EQ(find(a, 1, PathTerm::TableHit, PathVia::Direct).nonZero, 0u);
  EXPECT_EQ(find(a, 1, PathTerm::PatchNee, PathVia::Direct).nonZero, 0u);
  EXPECT_EQ(find(a, 1, PathTerm::LargeLightNee, PathVia::Direct).nonZero, 0u);
  EXPECT_GT(find(a, 2, PathTerm::TableHit, PathVia::Direct).meanSum, 0.0);
  EXPECT_GT(find(a, 2, PathTerm::PatchNee, PathVia::Direct).meanSum, 0.0);
  for (const VarianceCategory& c : b.categories)
    EXPECT_TRUE(c.term == int(PathTerm::LargeLightNee)) << "without a table, only NEE to the point light: " << c.name(8);
  const double z =
      std::abs(imageMean(a, small) - imageMean(b, kept)) / std::hypot(imageSe(a, small), imageSe(b, kept));
  fmt::print("  direct light: with table {:.6g}, without {:.6g}, z = {:.2f}\n", imageMean(a, small), imageMean(b, kept), z);
  ASSERT_GT(small.meanSum, 0.0);
  EXPECT_LT(z, 3.0);
}

// --max-depth D: no light of more than D bounces (patch NEE included, which is two bounces from its vertex).
TEST(VarianceReport, NothingLongerThanMaxDepth) {
  const SceneDesc desc = test::shadedLightRoom(12);
  const RenderScene table(desc, test::quickTable(desc));
  for (int depth : {1, 3}) {
    IntegratorOptions io;
    io.patchNee = PatchNee::Every;
    io.maxDepth = depth;
    const VarianceReport r = reportOf(table, io, 4, 1);
    int longest = -1;
    for (const VarianceCategory& c : r.categories) longest = std::max(longest, c.bounces);
    EXPECT_EQ(longest, depth) << "max depth " << depth;  // = : the longest paths do reach it
  }
}

// A caustic (light through a delta vertex past the first non-delta one) appears with a glass ball between the lamp
// and the floor, significantly (3σ) and only at two bounces or more (a floor vertex then at least one glass
// interface); with a diffuse ball of the same shape there is none.
TEST(VarianceReport, CausticsOnlyThroughGlass) {
  const SceneDesc glassDesc = ballBox(R"({"type": "dielectric", "ior": 1.5})");
  const SceneDesc diffuseDesc = ballBox(R"({"type": "diffuse", "albedo": 0.6})");
  const RenderScene glass(glassDesc), diffuse(diffuseDesc);
  const VarianceReport g = reportOf(glass, IntegratorOptions{}, 64, 1), d = reportOf(diffuse, IntegratorOptions{}, 64, 1);
  VarianceCategory caustic;
  for (const VarianceCategory& c : g.byTerm)
    if (c.via == int(PathVia::Delta)) caustic.meanSum += c.meanSum, caustic.varianceSum += c.varianceSum;
  for (const VarianceCategory& c : g.categories)
    if (c.via == int(PathVia::Delta)) {
      EXPECT_GE(c.bounces, 2) << c.name(8);
    }
  for (const VarianceCategory& c : d.categories) EXPECT_NE(c.via, int(PathVia::Delta)) << c.name(8);
  // σ of the caustics' sum bounded by the sum of their σs (Cauchy–Schwarz), so the test errs on the safe side.
  double se = 0;
  for (const VarianceCategory& c : g.byTerm)
    if (c.via == int(PathVia::Delta)) se += imageSe(g, c);
  fmt::print("  caustic share of the image {:.4f}, z = {:.1f}\n", caustic.meanSum / g.image.meanSum,
             imageMean(g, caustic) / se);
  EXPECT_GT(imageMean(g, caustic), 3.0 * se);
}
