// Adaptive sampling (render/loop/adaptive_sampling.h): the targets share the extras by the pixels' error; the image
// is the same for any number of threads and ranks; up to its uniform passes it is the uniform render's, bit for bit;
// the noisy pixels take the samples and the image agrees with a uniform render per 8 × 8 block within 3σ.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <mutex>

#include "common/formats/load_scene.h"
#include "render/loop/adaptive_sampling.h"
#include "tests/block_compare.h"
#include "tests/render_util.h"
#include "tests/test_util.h"
#include "tests/thread_comm.h"

using namespace firstshot;

namespace {

/// The shipped Cornell box at 32 × 32: its light's edges and the ceiling beside it are far noisier than its walls.
RenderScene cornell() {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 32;
  return RenderScene(desc);
}

/// An adaptive render of @p spp samples per pixel on average, on @p threads threads (through @p comm if given).
Film renderAdaptive(const Integrator& integrator, const RenderScene& scene, int spp, int threads, Comm* comm = nullptr,
                    bool adaptive = true, SamplerMode sampler = SamplerMode::Sobol, uint64_t seed = 7) {
  RenderOptions ro;
  ro.spp = spp;
  ro.seed = seed;
  ro.threads = threads;
  ro.adaptive = adaptive;
  ro.sampler = sampler;
  ro.comm = comm;
  return test::renderWith(integrator, scene, ro).film;
}

void addSamples(Film& film, int x, int y, int n, double spread) {
  for (int k = 0; k < n; ++k) {
    const float v = float(1.0 + (k % 2 ? spread : -spread));
    film.add(x, y, Color(v), Color(0.5f), Vec3(0, 1, 0));
  }
}

/// Per 8 × 8 block, gray: image @p a against @p b within 3σ, σ from both films' pixel variances over their samples
/// (a film of Sobol' samples makes its σ an upper bound).
void expectFilmsAgree(const Film& a, const Film& b, const std::string& what) {
  int worstBlock = -1;
  double worst = 0.0;
  for (int by = 0; by < a.height(); by += 8)
    for (int bx = 0; bx < a.width(); bx += 8) {
      double d = 0.0, var = 0.0;
      for (int y = by; y < std::min(by + 8, a.height()); ++y)
        for (int x = bx; x < std::min(bx + 8, a.width()); ++x) {
          const Vec3d ma = a.mean(x, y), mb = b.mean(x, y);
          const Vec3d va = a.variance(x, y), vb = b.variance(x, y);
          d += (ma.x + ma.y + ma.z - mb.x - mb.y - mb.z) / 3.0;
          // The gray mean's variance at most (Σ_c σ_c)² / 9, whatever the channels' correlation.
          const double sa = std::sqrt(va.x) + std::sqrt(va.y) + std::sqrt(va.z);
          const double sb = std::sqrt(vb.x) + std::sqrt(vb.y) + std::sqrt(vb.z);
          var += sa * sa / 9.0 / a.samples(x, y) + sb * sb / 9.0 / b.samples(x, y);
        }
      if (var == 0.0 && d == 0.0) continue;
      const double z = std::abs(d) / std::sqrt(var);
      if (z > worst) worst = z, worstBlock = (by / 8) * ((a.width() + 7) / 8) + bx / 8;
      EXPECT_LT(z, 3.0) << what << ": block (" << bx << ", " << by << ")";
    }
  fmt::print("  {}: worst block {} at {:.2f} sigma\n", what, worstBlock, worst);
}

}  // namespace

TEST(AdaptiveSampling, TheTargetsShareTheExtrasByTheNeighboursError) {
  // 8 × 8 pixels of 16 samples: a 2 × 2 square in a corner of variance 100 × the others'.
  Film film(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) addSamples(film, x, y, 16, x < 2 && y < 2 ? 1.0 : 0.1);
  const PixelRect all{0, 0, 8, 8};
  const double loud = 16.0 / 15.0, quiet = loud / 100.0;  // the samples' unbiased variances
  EXPECT_NEAR(pixelVariance(film, 0, 0), loud, 1e-9);
  // A pixel's weight is its neighbours' variance within its tile, over its own samples.
  EXPECT_NEAR(pixelErrorWeight(film, all, 0, 0), loud / 16.0, 1e-9);
  EXPECT_NEAR(pixelErrorWeight(film, all, 2, 2), (loud + 7.0 * quiet) / 8.0 / 16.0, 1e-9);
  // Within a tile two pixels wide: (1, 2) has 5 neighbours, two of them in the square.
  EXPECT_NEAR(pixelErrorWeight(film, {0, 0, 2, 8}, 1, 2), (2.0 * loud + 3.0 * quiet) / 5.0 / 16.0, 1e-9);
  // Not its own: a loud pixel among quiet ones weighs as they do.
  Film lone(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) addSamples(lone, x, y, 16, x == 5 && y == 5 ? 1.0 : 0.1);
  EXPECT_NEAR(pixelErrorWeight(lone, all, 5, 5), quiet / 16.0, 1e-9);
  // The extras follow the weights: over 200 rounds, the square's and the rest's sums within 4σ of their shares
  // of 64 a round (each pixel's rounding a uniform dither).
  double weights = 0.0, squareWeight = 0.0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      weights += pixelErrorWeight(film, all, x, y);
      if (x < 2 && y < 2) squareWeight += pixelErrorWeight(film, all, x, y);
    }
  double extrasOfTheSquare = 0.0, extrasOfTheRest = 0.0;
  const int rounds = 200;
  for (int round = 0; round < rounds; ++round) {
    const std::vector<uint32_t> t = adaptiveTargets(film, {all}, {0}, serialComm(), 3, round, 64.0);
    ASSERT_EQ(t.size(), 64u);
    for (int i = 0; i < 64; ++i) {
      ASSERT_GE(t[size_t(i)], 17u);
      (i % 8 < 2 && i / 8 < 2 ? extrasOfTheSquare : extrasOfTheRest) += double(t[size_t(i)] - 17);
    }
  }
  const double sigma = std::sqrt(64.0 * rounds / 12.0);
  EXPECT_NEAR(extrasOfTheSquare, 64.0 * squareWeight / weights * rounds, 4 * sigma);
  EXPECT_NEAR(extrasOfTheRest, 64.0 * (weights - squareWeight) / weights * rounds, 4 * sigma);
  EXPECT_GT(extrasOfTheSquare / 4.0, 5.0 * extrasOfTheRest / 60.0) << "the square's pixels take the most";
  // No error anywhere: no extras.
  Film flat(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) addSamples(flat, x, y, 4, 0.0);
  for (uint32_t t : adaptiveTargets(flat, {{0, 0, 4, 4}}, {0}, serialComm(), 3, 0, 16.0)) EXPECT_EQ(t, 5u);
  // At most kAdaptiveMaxExtra a round, however many extras one pixel's share would be.
  Film one(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) addSamples(one, x, y, 4, x == 1 && y == 0 ? 1.0 : 0.0);
  EXPECT_EQ(adaptiveTargets(one, {{0, 0, 4, 4}}, {0}, serialComm(), 3, 0, 1000.0)[0], 5u + kAdaptiveMaxExtra);
}

TEST(AdaptiveSampling, TheImageIsTheSameForAnyNumberOfThreadsAndRanks) {
  const RenderScene scene = cornell();
  auto path = makeIntegrator("path", IntegratorOptions{});
  path->preprocess(scene);
  const Film one = renderAdaptive(*path, scene, 40, 1);
  const std::vector<double> serial = test::filmValues(one);
  EXPECT_EQ(test::filmValues(renderAdaptive(*path, scene, 40, 3)), serial);
  uint32_t fewest = ~0u, most = 0;
  for (uint32_t n : one.sums().count) fewest = std::min(fewest, n), most = std::max(most, n);
  EXPECT_GE(fewest, uint32_t(kAdaptiveBase) + 1) << "every pixel takes one sample a round";
  EXPECT_GT(most, 2 * fewest) << "the noisiest pixels take more";
  for (int ranks : {2, 3}) {
    std::vector<double> root;
    std::mutex m;
    test::runRanks(ranks, [&](Comm& comm) {
      const Film film = renderAdaptive(*path, scene, 40, 1, &comm);
      std::lock_guard lock(m);
      if (comm.root()) root = test::filmValues(film);
    });
    EXPECT_EQ(root, serial) << ranks << " ranks";
  }
}

TEST(AdaptiveSampling, UpToItsUniformPassesTheImageIsTheUniformRenders) {
  const RenderScene scene = cornell();
  auto path = makeIntegrator("path", IntegratorOptions{});
  path->preprocess(scene);
  EXPECT_EQ(test::filmValues(renderAdaptive(*path, scene, kAdaptiveBase, 2)),
            test::filmValues(renderAdaptive(*path, scene, kAdaptiveBase, 2, nullptr, false)));
}

TEST(AdaptiveSampling, TheNoisyPixelsTakeTheSamplesAndTheImageAgreesWithAUniformRender) {
  const RenderScene scene = cornell();
  auto path = makeIntegrator("path", IntegratorOptions{});
  path->preprocess(scene);
  const int spp = test::kCompareBlocks ? 128 : 20;
  const Film adaptive = renderAdaptive(*path, scene, spp, 0);
  const Camera camera(scene.desc().camera);
  Film uniform(camera.width(), camera.height());
  RenderOptions ro;
  ro.spp = 4 * spp;
  ro.seed = 8;
  ro.sampler = SamplerMode::Independent;
  render(*path, camera, uniform, ro);
  // The samples' mean is --spp (less than one round's worth short or over).
  double samples = 0.0;
  for (uint32_t n : adaptive.sums().count) samples += n;
  const double pixels = double(camera.width() * camera.height());
  EXPECT_NEAR(samples / pixels, double(spp), 2.0);
  if (!test::kCompareBlocks) return;
  // The pixels' counts follow their error: the noisiest tenth (by the uniform render's variance) has more
  // than twice the samples of the quietest tenth.
  std::vector<std::pair<double, uint32_t>> byVariance;
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x) {
      const Vec3d v = uniform.variance(x, y);
      byVariance.emplace_back(v.x + v.y + v.z, adaptive.samples(x, y));
    }
  std::sort(byVariance.begin(), byVariance.end());
  const size_t tenth = byVariance.size() / 10;
  double quiet = 0.0, noisy = 0.0;
  for (size_t i = 0; i < tenth; ++i) quiet += byVariance[i].second, noisy += byVariance[byVariance.size() - 1 - i].second;
  fmt::print("  samples per pixel: quietest tenth {:.1f}, noisiest tenth {:.1f}\n", quiet / double(tenth),
             noisy / double(tenth));
  EXPECT_GT(noisy, 2.0 * quiet);
  expectFilmsAgree(adaptive, uniform, "path");
}

TEST(AdaptiveSampling, LightTracingTakesMoreCameraSideEstimatesWhereTheyAreNoisy) {
  // A mirror and a glass block seen by the camera: light tracing's pixels there are the path tracer's.
  const RenderScene scene(test::mirrorGlassScene());
  for (const char* name : {"light", "bdpt"}) {
    auto integrator = makeIntegrator(name, IntegratorOptions{});
    integrator->preprocess(scene);
    const int passes = test::kCompareBlocks ? 96 : kAdaptiveBase + 2;
    const Film one = renderAdaptive(*integrator, scene, passes, 1, nullptr, true, SamplerMode::Independent, 3);
    EXPECT_EQ(test::filmValues(renderAdaptive(*integrator, scene, passes, 3, nullptr, true, SamplerMode::Independent, 3)),
              test::filmValues(one)) << name << ", 3 threads";
    std::vector<double> root;
    std::mutex m;
    test::runRanks(2, [&](Comm& comm) {
      const Film film = renderAdaptive(*integrator, scene, passes, 1, &comm, true, SamplerMode::Independent, 3);
      std::lock_guard lock(m);
      if (comm.root()) root = test::filmValues(film);
    });
    EXPECT_EQ(root, test::filmValues(one)) << name << ", 2 ranks";
    // A pass stays one film sample a pixel.
    for (uint32_t n : one.sums().count) ASSERT_EQ(n, uint32_t(passes)) << name;
    // BDPT's camera side is all splats (its Li() adds nothing): its passes stay the uniform render's.
    const Film uniform = renderAdaptive(*integrator, scene, passes, 0, nullptr, false, SamplerMode::Independent, 3);
    if (std::string(name) == "bdpt") {
      EXPECT_EQ(test::filmValues(uniform), test::filmValues(one));
      continue;
    }
    EXPECT_NE(test::filmValues(uniform), test::filmValues(one)) << name << ": no extra estimate was taken";
    if (!test::kCompareBlocks) continue;
    const Film other = renderAdaptive(*integrator, scene, 4 * passes, 0, nullptr, false, SamplerMode::Independent, 4);
    expectFilmsAgree(one, other, name);
  }
}

TEST(AdaptiveSampling, RareBrightSamplesDoNotDarkenTheImage) {
  // The glass block's caustic on the floor, which the path tracer meets by chance: a pixel's rare bright samples.
  // Were a pixel's count to follow its own samples' variance, a bright sample would draw more samples that dilute it
  // (6.1% dark here, 40 seeds at 64 × 48). Its neighbours' variance does not depend on its own samples: image means
  // of adaptive and uniform renders of the same seeds, their mean difference within 3σ of 0.
  const RenderScene scene(test::mirrorGlassScene());
  auto path = makeIntegrator("path", IntegratorOptions{});
  path->preprocess(scene);
  const int seeds = test::kCompareBlocks ? 24 : 2;
  auto imageMean = [](const Film& film) {
    double sum = 0.0;
    for (int y = 0; y < film.height(); ++y)
      for (int x = 0; x < film.width(); ++x) {
        const Vec3d m = film.mean(x, y);
        sum += (m.x + m.y + m.z) / 3.0;
      }
    return sum / double(film.width() * film.height());
  };
  double sum = 0.0, sum2 = 0.0, uniformSum = 0.0;
  for (int s = 0; s < seeds; ++s) {
    const double uniform =
        imageMean(renderAdaptive(*path, scene, 64, 0, nullptr, false, SamplerMode::Independent, 100 + uint64_t(s)));
    const double d =
        imageMean(renderAdaptive(*path, scene, 64, 0, nullptr, true, SamplerMode::Independent, 100 + uint64_t(s))) -
        uniform;
    sum += d, sum2 += d * d, uniformSum += uniform;
  }
  const double mean = sum / seeds, se = std::sqrt((sum2 / seeds - mean * mean) / (seeds - 1));
  fmt::print("  adaptive − uniform: {:+.3f}% ± {:.3f}% of the image mean\n", 100 * mean / (uniformSum / seeds),
             100 * se / (uniformSum / seeds));
  if (test::kCompareBlocks) {
    EXPECT_LT(std::abs(mean), 3.0 * se);
  }
}
