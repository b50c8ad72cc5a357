#pragma once
/// @file block_compare.h
/// Image comparison of two integrators per 8×8-pixel block (the light-tracing and BDPT tests):
/// per-pass block means, σ from the passes, and the mirror-and-glass scene of those tests; and of
/// one integrator's two samplers (the sampler tests), σ from repetitions with different seeds.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "preprocess/preprocessor.h"
#include "render/integrators/integrator.h"
#include "render/loop/renderer.h"
#include "render/output/film.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot::test {

inline constexpr int kBlock = 8;

/// Under ASan+UBSan the image comparisons run their code for memory and UB only: blockMeans renders at most two
/// passes and expectBlocksAgree compares nothing (the Release build runs the statistics; two passes of each
/// integrator take the same code paths as hundreds, in a tenth of the time or less).
#ifdef FIRSTSHOT_UNDER_SANITIZERS
inline constexpr bool kCompareBlocks = false;
#else
inline constexpr bool kCompareBlocks = true;
#endif

/// The film's means and variances, pixel by pixel, for bit-for-bit comparisons.
inline std::vector<double> filmValues(const Film& film) {
  std::vector<double> v;
  for (int y = 0; y < film.height(); ++y)
    for (int x = 0; x < film.width(); ++x) {
      const Vec3d m = film.mean(x, y), q = film.variance(x, y);
      v.insert(v.end(), {m.x, m.y, m.z, q.x, q.y, q.z});
    }
  return v;
}

/// Adds to @p blocks (row-major kBlock × kBlock blocks of @p film, the last row and column
/// possibly partial) each block's gray mean of @p film.
inline void addBlockMeans(const Film& film, std::vector<Moments>& blocks) {
  const int w = film.width(), h = film.height(), bw = (w + kBlock - 1) / kBlock;
  std::vector<double> sum(blocks.size(), 0.0), count(blocks.size(), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t b = size_t(y / kBlock) * bw + size_t(x / kBlock);
      const Vec3d m = film.mean(x, y);
      sum[b] += (m.x + m.y + m.z) / 3.0, count[b] += 1;
    }
  for (size_t b = 0; b < blocks.size(); ++b) blocks[b].add(sum[b] / count[b]);
}

/// Per-pass gray means of every kBlock × kBlock block of @p scene rendered by @p integrator:
/// pass k is render() with firstSample = k and one sample, so the passes are independent samples.
inline std::vector<Moments> blockMeans(const Integrator& integrator, const RenderScene& scene, int passes, uint64_t seed = 1) {
  const Camera camera(scene.desc().camera);
  const int w = camera.width(), h = camera.height(), bw = (w + kBlock - 1) / kBlock, bh = (h + kBlock - 1) / kBlock;
  std::vector<Moments> blocks(size_t(bw) * bh);
  if (!kCompareBlocks) passes = std::min(passes, 2);
  for (int k = 0; k < passes; ++k) {
    Film film(w, h);
    render(integrator, camera, film, RenderOptions::pass(k, seed));
    addBlockMeans(film, blocks);
  }
  return blocks;
}

/// Per 8×8 block gray means of @p reps renders of @p spp each with seeds 1000 + r: one value per
/// repetition and block, so σ comes from independent repetitions (the Sobol' samples of one pixel
/// are not independent of each other; different seeds are).
inline std::vector<Moments> blockRepetitions(const Integrator& integrator, const RenderScene& scene, SamplerMode mode,
                                            int reps, int spp) {
  const Camera camera(scene.desc().camera);
  const int w = camera.width(), h = camera.height(), B = kBlock, bw = (w + B - 1) / B, bh = (h + B - 1) / B;
  std::vector<Moments> blocks(size_t(bw) * bh);
  for (int r = 0; r < reps; ++r) {
    Film film(w, h);
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = 1000 + uint64_t(r);
    ro.sampler = mode;
    render(integrator, camera, film, ro);
    addBlockMeans(film, blocks);
  }
  return blocks;
}

/// Per-block repetitions (blockRepetitions) of the independent sampler @p ind and the Sobol' one
/// @p sob: every block with light within 3σ of the difference, σ of each mean from its
/// repetitions; blocks black in both (the margins beside a box) are skipped, at least @p minLit
/// must be lit, and each must be known to @p maxRelSe (relative σ; else the test would be too weak).
inline void expectRepetitionsAgree(const std::string& name, const std::vector<Moments>& ind,
                                   const std::vector<Moments>& sob, int minLit, double maxRelSe = 0.05) {
  double worst = 0, rInd = 0, rSob = 0;
  int lit = 0;
  for (size_t b = 0; b < ind.size(); ++b) {
    if (ind[b].mean() == 0 && sob[b].mean() == 0) continue;
    const double se = std::hypot(ind[b].se(), sob[b].se()), z = std::abs(sob[b].mean() - ind[b].mean()) / se;
    EXPECT_LT(z, 3.0) << name << " block " << b << ": sobol " << sob[b].mean() << " ± " << sob[b].se()
                      << ", independent " << ind[b].mean() << " ± " << ind[b].se();
    EXPECT_LT(ind[b].se() / ind[b].mean(), maxRelSe) << name << " block " << b << ": too noisy to test";
    worst = std::max(worst, z), rInd += ind[b].se() / ind[b].mean(), rSob += sob[b].se() / sob[b].mean(), ++lit;
  }
  EXPECT_GE(lit, minLit) << name;
  fmt::print("{}: {} lit blocks, worst {:.2f}σ; mean relative σ of a block's repetition: independent {:.3f}%, "
             "sobol {:.3f}%\n", name, lit, worst, 100 * rInd / std::max(lit, 1), 100 * rSob / std::max(lit, 1));
}

/// Per-pixel noise of @p integrator: passes 2k and 2k + 1 (one sample per pixel each) give
/// d_k = mean over pixels of (x_2k − x_2k+1)²/2, an unbiased estimate of the mean pixel variance of one
/// pass; the d_k of different k are independent, so their mean has a σ from the samples.
inline Moments pixelVariance(const Integrator& integrator, const RenderScene& scene, int pairs) {
  const Camera camera(scene.desc().camera);
  const int w = camera.width(), h = camera.height();
  auto pass = [&](int k) {
    Film film(w, h);
    render(integrator, camera, film, RenderOptions::pass(k, 7));
    std::vector<double> v(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Vec3d m = film.mean(x, y);
        v[size_t(y) * w + x] = (m.x + m.y + m.z) / 3.0;
      }
    return v;
  };
  Moments d;
  for (int k = 0; k < pairs; ++k) {
    const std::vector<double> a = pass(2 * k), b = pass(2 * k + 1);
    double sum = 0;
    for (size_t p = 0; p < a.size(); ++p) sum += (a[p] - b[p]) * (a[p] - b[p]) / 2.0;
    d.add(sum / double(a.size()));
  }
  return d;
}

/// Two integrators' per-pass block means: every block within 3σ of the difference. @p knownBias: a bias of @p a
/// measured and documented elsewhere, relative to @p b's mean, that the difference may have beside its noise (0: none).
inline void expectBlocksAgree(const std::string& name, const std::vector<Moments>& a, const std::vector<Moments>& b,
                              double knownBias = 0.0) {
  ASSERT_EQ(a.size(), b.size()) << name;
  if (!kCompareBlocks) return;
  double worst = 0, worstRel = 0, worstDiff = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    const double se = std::hypot(a[k].se(), b[k].se());
    if (std::abs(a[k].mean() - b[k].mean()) > std::abs(worstDiff) * std::abs(b[k].mean()))
      worstDiff = (a[k].mean() - b[k].mean()) / std::abs(b[k].mean());
    const double z = std::max(0.0, std::abs(a[k].mean() - b[k].mean()) - knownBias * std::abs(b[k].mean())) / se;
    worst = std::max(worst, z);
    worstRel = std::max(worstRel, se / b[k].mean());
    EXPECT_LT(z, 3.0) << name << " block " << k << ": " << a[k].mean() << " ± " << a[k].se() << " against "
                      << b[k].mean() << " ± " << b[k].se();
  }
  fmt::print("{}: {} blocks, worst {:.2f}σ, largest relative σ {:.2f}%, largest difference {:+.2f}%\n", name, a.size(),
             worst, 100 * worstRel, 100 * worstDiff);
  EXPECT_LT(worstRel, 0.05) << name << ": too noisy to test";
}

/// Integrators @p a and @p b (makeIntegrator names, options @p io) on @p scene: every block within
/// 3σ of the difference (blockMeans, expectBlocksAgree).
inline void expectIntegratorsAgree(const std::string& name, const RenderScene& scene, const std::string& a, int passesA,
                                   const std::string& b, int passesB, const IntegratorOptions& io) {
  auto ia = makeIntegrator(a, io), ib = makeIntegrator(b, io);
  ia->preprocess(scene);
  ib->preprocess(scene);
  expectBlocksAgree(name, blockMeans(*ia, scene, passesA), blockMeans(*ib, scene, passesB));
}
/// Integrator @p integrator (a makeIntegrator name) against path tracing on @p d at 32×24, the
/// scene's max depth.
inline void expectAgreesWithPathTracing(const std::string& integrator, const std::string& name, SceneDesc d, int passes,
                                        int ptPasses) {
  d.camera.width = 32, d.camera.height = 24;
  const RenderScene scene(d, d.settings.patchSize);
  IntegratorOptions io;
  io.maxDepth = d.settings.maxDepth;
  expectIntegratorsAgree(name, scene, integrator, passes, "path", ptPasses, io);
}
/// The same with a first-shot table of @p d (Embree item buffers, R = 64) in the scene, which both
/// use (@p io: how; its maxDepth is the scene's): the same path space, so the same expected image,
/// table and all.
inline void expectAgreesWithPathTracingOnTable(const std::string& integrator, const std::string& name, SceneDesc d,
                                               int passes, int ptPasses, IntegratorOptions io) {
  d.camera.width = 32, d.camera.height = 24;
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene scene(d, preprocessScene(d, po));
  ASSERT_FALSE(scene.firstShot()->replacedLights.empty());
  io.maxDepth = d.settings.maxDepth;
  expectIntegratorsAgree(name, scene, integrator, passes, "path", ptPasses, io);
}
/// The same on the shipped scene scenes/@p name.json.
inline void expectAgreesWithPathTracing(const std::string& integrator, const std::string& name, int passes, int ptPasses) {
  expectAgreesWithPathTracing(integrator, name, loadScene(source("scenes/" + name + ".json")), passes, ptPasses);
}

/// A shooting integrator @p integrator (options @p io) shoots the small lights a first-shot table
/// replaces like all others: many-lights at 32×24 with and without a table give the same blocks
/// (@p passes each).
inline void expectTableLeavesImageUnchanged(const std::string& integrator, int passes, const IntegratorOptions& io = {}) {
  SceneDesc d = loadScene(source("scenes/many-lights.json"));
  d.camera.width = 32, d.camera.height = 24;
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  const RenderScene plain(d, d.settings.patchSize), withTable(d, preprocessScene(d, po));
  ASSERT_FALSE(withTable.firstShot()->replacedLights.empty());
  auto a = makeIntegrator(integrator, io), b = makeIntegrator(integrator, io);
  a->preprocess(withTable);
  b->preprocess(plain);
  expectBlocksAgree("many-lights with and without a table", blockMeans(*a, withTable, passes, 2), blockMeans(*b, plain, passes));
}

/// A mirror and a glass block seen by the camera, and the glass's caustic on the floor (32×24, max depth 8).
inline SceneDesc mirrorGlassScene() {
  return test::sceneFromJson(R"({"materials": {
      "white": {"type": "diffuse", "albedo": 0.7}, "red": {"type": "diffuse", "albedo": [0.7, 0.2, 0.1]},
      "mirror": {"type": "mirror", "specular": 0.9}, "glass": {"type": "dielectric", "ior": 1.5},
      "lamp": {"type": "diffuse", "emission": [6, 5, 4]}},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [2,1.5,2], "flip_normals": true},
               {"type": "quad", "material": "red", "vertices": [[0.01,0,0.2],[0.01,0,1.8],[0.01,1.5,1.8],[0.01,1.5,0.2]]},
               {"type": "quad", "material": "mirror", "vertices": [[1.99,0.2,1.8],[1.99,0.2,0.6],[1.99,1.2,0.6],[1.99,1.2,1.8]]},
               {"type": "box", "material": "glass", "min": [0.7,0.3,0.9], "max": [1.2,0.6,1.4]},
               {"type": "quad", "material": "lamp", "vertices": [[0.7,1.49,0.8],[1.3,1.49,0.8],[1.3,1.49,1.4],[0.7,1.49,1.4]]}],
    "camera": {"position": [0.6, 0.9, 0.05], "look_at": [1.3, 0.5, 1.5], "fov_y": 70, "resolution": [32, 24]},
    "settings": {"patch_size": 0.5, "max_depth": 8}})");
}

/// Every kind of light at once, on an open scene: a directional light, a spot, a point light and an
/// area light, over diffuse and glossy surfaces (32×24, max depth 6).
inline SceneDesc mixedLightsScene() {
  return test::sceneFromJson(R"({"materials": {
        "white": {"type": "diffuse", "albedo": 0.6}, "gloss": {"type": "glossy", "albedo": 0.2, "specular": 0.5, "exponent": 10},
        "lamp": {"type": "diffuse", "emission": [4, 3, 2]}},
      "shapes": [{"type": "quad", "material": "white", "vertices": [[-3,0,-3],[-3,0,3],[1,0,3],[1,0,-3]]},
                 {"type": "quad", "material": "gloss", "vertices": [[1,0,-3],[1,4,-3],[1,4,3],[1,0,3]]},
                 {"type": "box", "material": "white", "min": [-0.5,0,-0.3], "max": [0.1,0.7,0.3]},
                 {"type": "quad", "material": "lamp", "vertices": [[-1.2,1.5,-0.3],[-0.6,1.5,-0.3],[-0.6,1.5,0.3],[-1.2,1.5,0.3]]}],
      "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "irradiance": 1.5},
                 {"type": "spot", "position": [0.5, 1.8, 0.5], "direction": [0, -1, 0], "power": 20,
                  "inner_angle": 20, "outer_angle": 35},
                 {"type": "point", "position": [-1, 1, 1], "power": 10}],
      "camera": {"position": [-1.2, 3.2, -2.2], "look_at": [0.2, 0, 0.3], "fov_y": 55, "resolution": [32, 24]},
      "settings": {"patch_size": 0.5, "max_depth": 6}})");
}
}  // namespace firstshot::test
