// firstshot-light-accuracy: how the area-light tessellation (preprocess/light_tessellation.h) trades
// light samples and preprocess time against the error of the first-shot irradiance.
//
// For one scene: a reference table with a very fine uniform tessellation (--reference), then one
// table per configuration (automatic at each --tolerances value, uniform at each --patch-sizes value).
// Per configuration (one Markdown table row): light samples, preprocess seconds, and the error of the
// per-patch irradiance FirstShotTable::irradiance(j) (channel mean) against the reference:
//   L1  = Σ_j A_j |E_j − E_ref,j| / Σ_j A_j E_ref,j   (area-weighted relative L1)
//   L2  = √(Σ_j A_j (E_j − E_ref,j)² / Σ_j A_j E_ref,j²)
//   max = max_j |E_j − E_ref,j| / E_ref,j over patches with E_ref,j ≥ 1% of the area-weighted mean.
// The difference holds the tessellation's error and the item buffers' visibility aliasing (which moves
// with the sample positions); the column "rule" isolates the first: the largest relative error of the
// unoccluded vertex rule against the exact point-to-polygon integral at both sides of every patch
// centroid in front of a single-face area light: "rule" at points that see the whole light above their
// horizon (relative), "rule, cut" where the patch's plane cuts the light (relative to the irradiance
// the point would receive facing the light). "max patch" names the worst patch's shape and its
// reference irradiance relative to the area-weighted mean.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "common/formats/load_scene.h"
#include "common/lights/form_factors.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/util/cli.h"
#include "preprocess/light_tessellation.h"
#include "preprocess/preprocessor.h"

namespace {

using namespace firstshot;

struct Run {
  FirstShotTable table;
  double seconds = 0;
};

Run preprocess(const SceneDesc& scene, double lightPatchSize, double tolerance, const std::string& backend) {
  PreprocessOptions o = defaultOptions(scene);
  o.settings.lightPatchSize = lightPatchSize;
  o.settings.lightTolerance = tolerance;
  o.settings.backend = backend;
  o.quiet = true;
  const auto t0 = std::chrono::steady_clock::now();
  Run r;
  r.table = preprocessScene(scene, o);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

double mean(const Color& c) { return (double(c.x) + c.y + c.z) / 3.0; }

/// Worst error of the unoccluded vertex rule at the patch centroids (both sides; see the file comment).
VertexRuleError ruleError(const SceneDesc& scene, const FirstShotTable& t, double lightPatchSize, double tolerance) {
  VertexRuleError worst;
  std::vector<std::pair<Vec3d, Vec3d>> points;
  for (const Patch& p : t.mesh.patches)
    for (double side : {1.0, -1.0}) points.emplace_back(Vec3d(p.centroid), side * Vec3d(p.normal));
  for (uint32_t li : t.replacedLights) {
    const LightDesc& l = scene.lights[li];
    if (l.type != LightType::Area || scene.shapes[l.shape].faces.size() != 1) continue;
    const LightTessellation lt = tessellateAreaLight(scene, l.shape, lightPatchSize, tolerance, kNoLightSampleBudget);
    const VertexRuleError e = vertexRuleError(scene.shapes[l.shape], lt, points);
    worst.cut = std::max(worst.cut, e.cut), worst.uncut = std::max(worst.uncut, e.uncut);
  }
  return worst;
}

void report(const SceneDesc& scene, const std::string& label, const Run& run, const Run& ref, double lps, double tol) {
  const FirstShotTable& t = run.table;
  double sumA = 0, sumAE = 0, l1 = 0, l2 = 0, ref2 = 0, worst = 0;
  uint32_t worstPatch = 0;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const double a = t.mesh.patches[j].area, e = mean(t.irradiance(j)), er = mean(ref.table.irradiance(j));
    sumA += a, sumAE += a * er, l1 += a * std::abs(e - er), l2 += a * (e - er) * (e - er), ref2 += a * er * er;
  }
  const double meanE = sumAE / sumA;
  for (uint32_t j = 0; j < t.mesh.size(); ++j) {
    const double e = mean(t.irradiance(j)), er = mean(ref.table.irradiance(j));
    if (er >= 0.01 * meanE && std::abs(e - er) / er > worst) worst = std::abs(e - er) / er, worstPatch = j;
  }
  const VertexRuleError rule = ruleError(scene, t, lps, tol);
  const Patch& wp = t.mesh.patches[worstPatch];
  std::printf("| %s | %zu | %.2f | %.3f%% | %.3f%% | %.2f%% (%s, E/mean %.3f) | %.3f%% | %.4f%% |\n", label.c_str(),
              t.samples.size(), run.seconds, 100 * l1 / sumAE, 100 * std::sqrt(l2 / ref2), 100 * worst,
              scene.shapes[wp.shape].name.c_str(), mean(ref.table.irradiance(worstPatch)) / meanE, 100 * rule.uncut,
              100 * rule.cut);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"firstshot-light-accuracy: light samples, time and first-shot irradiance error vs the light tessellation"};
  std::string scenePath, backend = "gl", referenceFile;
  double reference = 0.005;
  std::vector<double> tolerances = {0.04, 0.01, 0.0025};
  std::vector<double> patchSizes;
  app.add_option("scene", scenePath, "scene file")->required();
  app.add_option("--reference", reference, "uniform light_patch_size of the reference table, m");
  app.add_option("--tolerances", tolerances, "light_tolerance values (automatic tessellation)")->delimiter(',');
  app.add_option("--patch-sizes", patchSizes, "uniform light_patch_size values, m")->delimiter(',');
  app.add_option("--backend", backend, "gl | embree");
  app.add_option("--reference-file", referenceFile, "read the reference table from this .fsd if it exists, else write it there");
  CLI11_PARSE(app, argc, argv);
  return runTool("firstshot-light-accuracy", [&] {
    const SceneDesc scene = loadScene(scenePath);
    Run ref;
    if (!referenceFile.empty() && std::filesystem::exists(referenceFile)) {
      ref.table = readFirstShot(referenceFile, hashScene(scene));
      reference = ref.table.settings.lightPatchSize;
    } else {
      ref = preprocess(scene, reference, 0.01, backend);
      if (!referenceFile.empty()) writeFirstShot(referenceFile, ref.table);
    }
    std::printf("%s: %u patches; reference: uniform %g m, %zu samples, %.1f s\n\n", scenePath.c_str(), ref.table.mesh.size(),
                reference, ref.table.samples.size(), ref.seconds);
    std::printf("| tessellation | samples | seconds | L1 | L2 | max patch | rule | rule, cut |\n|---|---|---|---|---|---|---|---|\n");
    for (double tol : tolerances) report(scene, "auto, tolerance " + std::to_string(tol), preprocess(scene, 0, tol, backend), ref, 0, tol);
    for (double lps : patchSizes) report(scene, "uniform " + std::to_string(lps) + " m", preprocess(scene, lps, 0.01, backend), ref, lps, 0.01);
    return 0;
  });
}
