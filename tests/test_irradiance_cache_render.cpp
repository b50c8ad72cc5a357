// The irradiance cache integrator against path tracing. In the Cornell box with a point light
// (direct light exact, so the error left is the cache's), on the very same camera rays:
// - the error of Ward's 1988 method grows about linearly with a (the fit is printed) while the
//   record count falls;
// - Ward & Heckbert's gradients lower the error at the same a;
// - several bounces (B = 2) match a path tracer limited to the same path length;
// - past the last bounce the ambient value adds exactly ρ·ambient.
// In the Cornell box with its area light: first-shot + cache and NEE + cache agree, and the
// first-shot run traces no shadow rays at the cache's hemisphere samples.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <memory>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/integrators/path/integrator.h"
#include "tests/irradiance_cache_util.h"

using namespace firstshot;

namespace {

constexpr int kSize = 32;      // image side, pixels
constexpr int kSpp = 4;        // camera samples per pixel
constexpr int kPathPerRay = 48;
constexpr uint64_t kSeed = 5;

IrradianceCacheSettings ward1988(float a, int bounces) {
  IrradianceCacheSettings s;
  s.accuracy = a;
  s.samples = 512;
  s.bounces = bounces;
  s.gradients = false;
  s.neighbourClamp = false;
  s.footprintMin = 0.0f;
  s.footprintMax = std::numeric_limits<float>::infinity();
  s.twoPass = true;
  s.missRecords = true;  // Ward's: a render sample that finds no record makes one
  s.seed = kSeed;
  return s;
}

/// One reference per bounce count, shared by the tests of this file.
class IrradianceCacheVsPath : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    desc_ = new SceneDesc(test::cornellWithPointLight(kSize));
    scene_ = new RenderScene(*desc_);
    camera_ = new Camera(desc_->camera);
  }
  static void TearDownTestSuite() {
    delete camera_;
    delete scene_;
    delete desc_;
    delete ref1_;
    delete ref2_;
  }
  /// The path-traced reference for B cache bounces: paths of B + 1 bounces.
  static const test::PairedReference& reference(int bounces) {
    test::PairedReference*& r = bounces == 1 ? ref1_ : ref2_;
    if (!r) {
      IntegratorOptions io;
      io.maxDepth = bounces + 1;
      PathIntegrator path(io);
      path.preprocess(*scene_);
      r = new test::PairedReference(test::pairedReference(path, *camera_, kSpp, kPathPerRay, kSeed));
    }
    return *r;
  }
  struct Run {
    double error;
    size_t records;
  };
  static Run run(const IrradianceCacheSettings& s) {
    IntegratorOptions io;
    io.maxDepth = s.bounces + 1;
    IrradianceCacheIntegrator ic(io, s);
    ic.preprocess(*scene_);
    return {test::pairedRelativeRmse(ic, *camera_, reference(s.bounces)), ic.cache().size()};
  }

  static SceneDesc* desc_;
  static RenderScene* scene_;
  static Camera* camera_;
  static test::PairedReference *ref1_, *ref2_;
};
SceneDesc* IrradianceCacheVsPath::desc_ = nullptr;
RenderScene* IrradianceCacheVsPath::scene_ = nullptr;
Camera* IrradianceCacheVsPath::camera_ = nullptr;
test::PairedReference* IrradianceCacheVsPath::ref1_ = nullptr;
test::PairedReference* IrradianceCacheVsPath::ref2_ = nullptr;

/// The Cornell box at 32 × 32, and a picture of its view with 8 × 8 pixels (a pilot's fill is made for such).
SceneDesc cornell32() {
  SceneDesc d = loadScene(test::source("scenes/cornell.json"));
  d.camera.width = d.camera.height = 32;
  return d;
}
/// The cache's defaults, without progress on stderr.
IrradianceCacheSettings quietSettings() {
  IrradianceCacheSettings s;
  s.quiet = true;
  return s;
}
CameraDesc eighth(const CameraDesc& camera) {
  CameraDesc c = camera;
  c.width = c.height = 8;
  return c;
}

}  // namespace

TEST_F(IrradianceCacheVsPath, ErrorGrowsLinearlyWithAccuracyAndRecordsFall) {
  const std::vector<double> as = {0.05, 0.1, 0.2, 0.3, 0.4};
  std::vector<double> errors;
  std::vector<size_t> records;
  fmt::print("     a   rel. RMSE   records\n");
  for (double a : as) {
    const Run r = run(ward1988(float(a), 1));
    errors.push_back(r.error);
    records.push_back(r.records);
    fmt::print("  {:.2f}   {:.5f}   {:7}\n", a, r.error, r.records);
  }
  const test::LineFit fit = test::fitLine(as, errors);
  fmt::print("linear fit: rel. RMSE = {:.5f} + {:.5f}·a, r² = {:.3f}\n", fit.intercept, fit.slope, fit.r2);
  for (size_t i = 1; i < as.size(); ++i) EXPECT_LT(records[i], records[i - 1]) << "a = " << as[i];
  EXPECT_GT(fit.slope, 0.0);
  EXPECT_GT(fit.r2, 0.9);
  EXPECT_GT(errors.back(), 2.0 * errors.front());
  EXPECT_LT(errors.front(), 0.02);  // a = 0.05: within 2 % of the path-traced image
}

TEST_F(IrradianceCacheVsPath, GradientsLowerTheError) {
  double sumPlain = 0, sumGradients = 0;
  for (float a : {0.2f, 0.3f, 0.4f}) {
    IrradianceCacheSettings s = ward1988(a, 1);
    const Run plain = run(s);
    s.gradients = true;
    const Run withGradients = run(s);
    fmt::print("a = {}: rel. RMSE {:.5f} without gradients, {:.5f} with\n", a, plain.error, withGradients.error);
    EXPECT_LT(withGradients.error, plain.error) << "a = " << a;
    sumPlain += plain.error;
    sumGradients += withGradients.error;
  }
  EXPECT_LT(sumGradients, 0.85 * sumPlain);
}

// Each test spells out its own cache settings (accuracy, samples, bounces differ), as in test_irradiance_cache_file.cpp.
TEST_F(IrradianceCacheVsPath, TwoBouncesMatchPathsOfThreeBounces) {
  // Gradients, footprint and neighbour clamping with B = 2 (the footprint clamp scaled to this
  // tiny image: the valid domains span at least half a pixel).
  IrradianceCacheSettings s;
  s.footprintMin = 0.5f;
  s.accuracy = 0.15f;
  s.samples = 256;
  s.bounces = 2;
  s.twoPass = true;
  s.seed = kSeed;
  const Run r = run(s);
  fmt::print("B = 2, a = 0.15, N = 256, clamps on: rel. RMSE {:.5f} against paths of 3 bounces, {} records\n", r.error, r.records);
  EXPECT_LT(r.error, 0.03);
}

TEST_F(IrradianceCacheVsPath, AmbientPastTheLastBounce) {
  // B = 0: no cache, every diffuse surface reflects ρ·ambient on top of its direct light.
  const Color ambient(0.2f, 0.1f, 0.05f);
  IntegratorOptions io;
  auto render = [&](const Color& amb) {
    IrradianceCacheSettings s = ward1988(0.2f, 0);
    s.pathContinuation = false;  // Ward's ambient term instead of paths
    s.ambient = amb;
    IrradianceCacheIntegrator ic(io, s);
    ic.preprocess(*scene_);
    Film film(kSize, kSize);
    RenderOptions ro;
    ro.spp = 2;
    firstshot::render(ic, *camera_, film, ro);
    EXPECT_EQ(ic.cache().size(), 0u);
    return film;
  };
  const Film with = render(ambient), without = render(Color(0.0f));
  double worst = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Vec3d expected = with.albedo(x, y) * Vec3d(ambient);  // mean albedo of the pixel's samples × ambient
      worst = std::max(worst, glm::length(with.mean(x, y) - without.mean(x, y) - expected));
    }
  fmt::print("ambient: largest |difference − ρ·ambient| = {:.2e}\n", worst);
  EXPECT_LT(worst, 1e-5);
}

TEST(IrradianceCacheFirstShot, AgreesWithNeeAndGathersFirstShotLight) {
  // The Cornell box with its (small) area light: NEE + cache against first-shot + cache, same
  // settings and seeds. At the camera-visible vertex both take the light by NEE (exact mode) with
  // the same random numbers; the cache's hemisphere samples see NEE-lit surfaces in one run and
  // first-shot-lit ones (patch-averaged, no shadow rays) in the other.
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = kSize;
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = 128;
  po.settings.patchSize = 0.025;
  po.settings.lightPatchSize = 0.05;
  po.quiet = true;
  FirstShotTable table = preprocessScene(desc, po);
  ASSERT_EQ(table.replacedLights.size(), 1u);
  const RenderScene nee(desc), firstShot(desc, std::move(table));
  IrradianceCacheSettings s = ward1988(0.15f, 1);
  s.gradients = true;
  const Camera camera(desc.camera);
  RenderOptions ro;
  ro.spp = 8;
  ro.seed = kSeed;
  struct Result {
    Film film{kSize, kSize};
    RenderStats stats;
    size_t records;
  };
  IntegratorOptions io;
  io.patchNee = PatchNee::Off;  // the lit patches as sampled emitters add shadow rays of their own
  // One shadow ray per light: the camera vertex draws the same numbers for the light whether it is
  // kept (NEE run) or replaced (first-shot run); a light tree draws per group, kept then replaced.
  io.lightSampler = LightStrategy::All;
  auto render = [&](const RenderScene& scene) {
    IrradianceCacheIntegrator ic(io, s);
    ic.preprocess(scene);
    Result r;
    r.stats = firstshot::render(ic, camera, r.film, ro);
    r.records = ic.cache().size();
    return r;
  };
  const Result a = render(nee), b = render(firstShot);
  double sumA = 0, sumB = 0, sumD2 = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c) {
        const double va = a.film.mean(x, y)[c], vb = b.film.mean(x, y)[c];
        sumA += va, sumB += vb, sumD2 += (va - vb) * (va - vb);
      }
  const double n = 3.0 * kSize * kSize, rel = (sumB - sumA) / sumA, rms = std::sqrt(sumD2 / n) / (sumA / n);
  fmt::print("NEE + cache: mean {:.5f}, {} records, {} rays; first-shot + cache: mean {:.5f}, {} records, {} rays\n",
             sumA / n, a.records, a.stats.rays, sumB / n, b.records, b.stats.rays);
  fmt::print("relative difference of the means {:+.4f}, RMS pixel difference {:.4f} of the mean\n", rel, rms);
  EXPECT_LT(std::abs(rel), 0.01);
  EXPECT_LT(rms, 0.05);
  EXPECT_NEAR(double(b.records) / double(a.records), 1.0, 0.1);  // placement is mostly geometric
  // No shadow rays at the hemisphere samples' hits: well under the NEE run's rays.
  EXPECT_LT(double(b.stats.rays), 0.7 * double(a.stats.rays));
}

TEST(IrradianceCacheSpecular, MirrorAndGlossySurfacesMatchPathTracing) {
  // The point-lit Cornell box with a mirror back wall and a glossy (stretched Phong) tall block,
  // albedos halved so that four cached bounces hold all but ~0.5 % of the light: against full
  // path tracing on the same camera rays.
  SceneDesc desc = test::cornellWithPointLight(24);
  for (MaterialDesc& m : desc.materials) m.albedo *= 0.5f;
  MaterialDesc mirror, glossy;
  mirror.name = "mirror", mirror.type = MaterialType::Mirror, mirror.specular = Color(0.9f);
  glossy.name = "glossy", glossy.type = MaterialType::Glossy, glossy.albedo = Color(0.25f), glossy.specular = Color(0.3f);
  glossy.exponent = 8.0f;
  desc.materials.push_back(mirror);
  desc.materials.push_back(glossy);
  for (ShapeDesc& s : desc.shapes) {
    if (s.name.find("back wall") != std::string::npos) s.material = int(desc.materials.size()) - 2;
    if (s.name.find("tall block") != std::string::npos) s.material = int(desc.materials.size()) - 1;
  }
  const RenderScene scene(desc);
  const Camera camera(desc.camera);
  PathIntegrator path(IntegratorOptions{});
  path.preprocess(scene);
  const test::PairedReference ref = test::pairedReference(path, camera, kSpp, 2 * kPathPerRay, kSeed);
  IrradianceCacheSettings s;
  s.accuracy = 0.2f;
  s.samples = 128;
  s.bounces = 4;
  s.footprintMin = 0.5f;
  s.twoPass = true;
  s.seed = kSeed;
  IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  ic.preprocess(scene);
  const test::PairedError e = test::pairedError(ic, camera, ref, 16);
  fmt::print("mirror + glossy, B = 4: rel. RMSE {:.4f}, mean {:+.4f} ± {:.4f} against full path tracing, {} records\n",
             e.relRmse, e.meanDiff, e.meanDiffSe, ic.cache().size());
  EXPECT_LT(e.relRmse, 0.03);
  EXPECT_LT(std::abs(e.meanDiff), 3 * e.meanDiffSe + 0.005);
  // The same measures do see a real error: one cached bounce instead of four, nothing past it.
  s.bounces = 1;
  s.pathContinuation = false;
  IrradianceCacheIntegrator short1(IntegratorOptions{}, s);
  short1.preprocess(scene);
  const test::PairedError e1 = test::pairedError(short1, camera, ref, 16);
  fmt::print("B = 1: rel. RMSE {:.4f}, mean {:+.4f} ± {:.4f}\n", e1.relRmse, e1.meanDiff, e1.meanDiffSe);
  EXPECT_GT(e1.relRmse, 0.03);
  EXPECT_GT(std::abs(e1.meanDiff), 5 * e1.meanDiffSe + 0.005);
}

// limitPreprocessRays (--integrator auto's pilot budget): the fill stops after the first batch past the limit, at the
// same place for one and two threads, well short of the whole fill.
TEST(IrradianceCacheFill, StopsPastItsRayLimit) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = 48, desc.camera.height = 48;
  const RenderScene scene(desc);
  IrradianceCacheSettings s;
  s.twoPass = true;
  s.quiet = true;
  IrradianceCacheIntegrator whole(IntegratorOptions{}, s);
  whole.preprocess(scene);
  const uint64_t all = whole.preprocessRayCount(), limit = all / 10;
  uint64_t counts[2] = {0, 0};
  for (int t = 1; t <= 2; ++t) {
    s.threads = t;
    IrradianceCacheIntegrator part(IntegratorOptions{}, s);
    part.limitPreprocessRays(limit);
    part.preprocess(scene);
    counts[t - 1] = part.preprocessRayCount();
  }
  fmt::print("fill rays: whole {}, limited to {}: {}\n", all, limit, counts[0]);
  EXPECT_GT(counts[0], limit);
  EXPECT_LT(counts[0], all / 2);
  EXPECT_EQ(counts[0], counts[1]);
}

// preprocessFor (the pilot's fill) gathers about one level-0 record in two twice: |E − E'|/√2 is one draw of its
// standard error. perturbPreprocessing then redraws every level-0 record's E by the records' relative noise so
// measured (the same for a seed, another for another seed) and leaves the other levels and every position alone.
TEST(IrradianceCacheFill, ThePilotsFillMeasuresItsRecordsOwnNoiseAndRedrawsThem) {
  const SceneDesc desc = cornell32();
  const RenderScene scene(desc);
  const CameraDesc coarse = eighth(desc.camera);
  IrradianceCacheSettings s = quietSettings();
  auto filled = [&] {
    auto ic = std::make_unique<IrradianceCacheIntegrator>(IntegratorOptions{}, s);
    ic->preprocessFor(scene, coarse);
    return ic;
  };
  const auto ic = filled();
  const std::vector<IrradianceRecord> before = ic->cache().records(0), deeper = ic->cache().records(1);
  size_t measured = 0;
  double spread2 = 0, value2 = 0;
  for (const IrradianceRecord& r : before)
    if (r.spread.x >= 0.0f)
      ++measured, spread2 += luminance(r.spread) * luminance(r.spread), value2 += luminance(r.E) * luminance(r.E);
  fmt::print("{} level-0 records, {} gathered twice, their relative noise {:.4f}\n", before.size(), measured,
             std::sqrt(spread2 / value2));
  ASSERT_GT(measured, 0u);
  EXPECT_GT(measured, before.size() / 4);  // about one in two
  EXPECT_LT(measured, before.size());
  EXPECT_GT(spread2, 0.0);
  ic->perturbPreprocessing(7);
  const std::vector<IrradianceRecord> after = ic->cache().records(0);
  ASSERT_EQ(after.size(), before.size());
  double change2 = 0, sum2 = 0;
  for (size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].p, before[i].p);
    const double d = luminance(after[i].E) - luminance(before[i].E);
    change2 += d * d, sum2 += luminance(before[i].E) * luminance(before[i].E);
  }
  const double relative = std::sqrt(spread2 / value2), changed = std::sqrt(change2 / sum2);
  fmt::print("redrawn: relative change {:.4f}\n", changed);
  EXPECT_GT(changed, 0.5 * relative);  // a normal draw per record: the RMS change is the relative noise, ±
  EXPECT_LT(changed, 2.0 * relative);
  const std::vector<IrradianceRecord> deeperAfter = ic->cache().records(1);
  ASSERT_EQ(deeperAfter.size(), deeper.size());
  for (size_t i = 0; i < deeper.size(); ++i) EXPECT_EQ(deeperAfter[i].E, deeper[i].E);
  const auto again = filled(), other = filled();
  again->perturbPreprocessing(7);
  other->perturbPreprocessing(8);
  const std::vector<IrradianceRecord> a = again->cache().records(0), b = other->cache().records(0);
  size_t same = 0;
  for (size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(a[i].E, after[i].E) << i;
    same += b[i].E == after[i].E;
  }
  EXPECT_LT(same, after.size() / 2);
}

// preprocessFor a coarser picture (--integrator auto's pilot): the finer picture's samples that its records do not
// cover take one path each instead of a record of their own, the same for one and two threads, and the image agrees
// with the path tracer's (within 3σ of the two images' means and the cache's interpolation bias, +0.4% in this box
// at the defaults: 1.5% allowed).
TEST(IrradianceCacheFill, ACoarserPicturesRecordsServeAFinerPictureWithPathsWhereNoneIsValid) {
  const SceneDesc desc = cornell32();
  const RenderScene scene(desc);
  const CameraDesc coarse = eighth(desc.camera);
  IrradianceCacheSettings s = quietSettings();
  IrradianceCacheStats stats[2];
  std::unique_ptr<test::RenderRun> run[2];
  for (int t = 1; t <= 2; ++t) {
    s.threads = t;
    IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
    ic.preprocessFor(scene, coarse);
    run[t - 1] = std::make_unique<test::RenderRun>(test::renderWith(ic, scene, 32, 3, t));
    stats[t - 1] = ic.stats();
  }
  const Film& film = run[0]->film;
  EXPECT_EQ(stats[0].privateRecords, 0u);
  EXPECT_GT(stats[0].missPaths, 0u) << "the 8 x 8 picture's records cover every sample of the 32 x 32 one?";
  EXPECT_EQ(stats[0].missPaths, stats[1].missPaths);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ASSERT_EQ(film.mean(x, y), run[1]->film.mean(x, y)) << x << ", " << y;
  const test::RenderRun path = test::renderPath(scene, IntegratorOptions{}, 64, 4);
  for (int c = 0; c < 3; ++c) {
    double mc = 0, sc = 0, mp = 0, sp = 0;
    test::imageMean(film, c, mc, sc);
    test::imageMean(path.film, c, mp, sp);
    EXPECT_NEAR(mc, mp, 3.0 * std::hypot(sc, sp) + 0.015 * mp) << "channel " << c;
  }
}

// keyMissPaths (the pilot's measure of what the paths of missed samples add): with a salt, a sample the records miss
// draws its path from a stream of its own, so that the same salt renders the same picture and another redraws those
// paths alone: at most one pixel changes per path (the rest of each sample stays as it was), and the picture's mean
// stays within 3σ.
TEST(IrradianceCacheFill, KeyedMissPathsAreRedrawnAlone) {
  const SceneDesc desc = cornell32();
  const RenderScene scene(desc);
  IrradianceCacheSettings s = quietSettings();
  s.threads = 1;
  IrradianceCacheIntegrator ic(IntegratorOptions{}, s);
  ic.preprocessFor(scene, eighth(desc.camera));
  const uint64_t salts[3] = {11, 11, 12};
  std::unique_ptr<test::RenderRun> run[3];
  uint64_t misses = 0;
  for (int k = 0; k < 3; ++k) {
    ic.keyMissPaths(salts[k]);
    const uint64_t before = ic.stats().missPaths;
    run[k] = std::make_unique<test::RenderRun>(test::renderWith(ic, scene, 4, 3, 1));
    misses = ic.stats().missPaths - before;
  }
  size_t changed = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      ASSERT_EQ(run[0]->film.mean(x, y), run[1]->film.mean(x, y)) << x << ", " << y;
      changed += run[0]->film.mean(x, y) != run[2]->film.mean(x, y);
    }
  fmt::print("{} paths of missed samples, {} of 1024 pixels changed\n", misses, changed);
  EXPECT_GT(changed, 0u);
  EXPECT_LE(changed, misses);
  for (int c = 0; c < 3; ++c) {
    double ma = 0, sa = 0, mb = 0, sb = 0;
    test::imageMean(run[0]->film, c, ma, sa);
    test::imageMean(run[2]->film, c, mb, sb);
    EXPECT_NEAR(ma, mb, 3.0 * std::hypot(sa, sb)) << "channel " << c;
  }
}
