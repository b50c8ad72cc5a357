// firstshot-preprocess-accuracy: the preprocessor's r_ij against the exact value as a function of the
// item-buffer resolution R and of the patch width in pixels, for both estimators and back ends.
//
// Scene: one isotropic point light 1 m over a 2 m × 2 m diffuse floor (nothing occludes), the floor cut
// into square patches of several sizes. The exact factor of patch j is Ω_j/(4π A_j) (Ω_j: the solid
// angle of the patch from the light). One CSV row per (back end, estimator, R, patch size, width bin),
// the bins being [2^k, 2^(k+1)) pixels of the patch's width on its cube face (√ of its projected area).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "common/formats/json/scene_json.h"
#include "common/lights/form_factors.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/util/cli.h"
#include "preprocess/preprocessor.h"

namespace {

using namespace firstshot;

const char* kSceneJson = R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
  "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
  "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}], "settings": {"patch_size": 0.1}})";

/// Width in pixels of patch @p p seen from @p eye on the cube face of its centroid's dominant axis at
/// resolution R: √(projected area) / pixel size (a face spans [-1, 1], so a pixel is 2/R wide).
double widthInPixels(const Patch& p, const Vec3d& eye, int R) {
  const Vec3d c = Vec3d(p.centroid) - eye;
  const Vec3d a = glm::abs(c);
  const int major = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = (major + 1) % 3, v = (major + 2) % 3;
  Vec2d q[4];
  for (uint32_t k = 0; k < p.count; ++k) {
    const Vec3d d = Vec3d(p.v[k]) - eye;
    q[k] = Vec2d(d[u], d[v]) / std::abs(d[major]);
  }
  double area2 = 0;
  for (uint32_t k = 0; k < p.count; ++k) area2 += q[k].x * q[(k + 1) % p.count].y - q[(k + 1) % p.count].x * q[k].y;
  return std::sqrt(std::abs(area2) / 2) / (2.0 / R);
}

struct Bin {
  double sumSq = 0, sumAbs = 0, max = 0;
  int n = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"firstshot-preprocess-accuracy: r_ij error against the exact value vs R and patch width in pixels (CSV)"};
  std::string output = "-";
  std::vector<int> resolutions = {64, 128, 256, 512, 1024};
  std::vector<double> patchSizes = {0.2, 0.1, 0.05, 0.025, 0.0125};
  std::vector<std::string> backends = {"gl", "embree"};
  std::vector<std::string> estimators = {"pixels", "analytic"};
  int threads = 0;
  app.add_option("-o,--output", output, "CSV file (- for stdout)");
  app.add_option("--resolutions", resolutions, "item-buffer resolutions R")->delimiter(',');
  app.add_option("--patch-sizes", patchSizes, "patch edges in metres")->delimiter(',');
  app.add_option("--backends", backends, "gl and/or embree")->delimiter(',');
  app.add_option("--estimators", estimators, "pixels and/or analytic")->delimiter(',');
  app.add_option("--threads", threads, "preprocessor threads (0: one per core)");
  CLI11_PARSE(app, argc, argv);
  return runTool("firstshot-preprocess-accuracy", [&] {
    SceneDesc scene = parseSceneJson(kSceneJson, "point-over-plane (built in)");
    validateScene(scene);
    const Vec3d eye(0, 1, 0);
    FILE* out = output == "-" ? stdout : std::fopen(output.c_str(), "w");
    if (!out) throw std::runtime_error("cannot write " + output);
    std::fprintf(out,
                 "# r_ij of a point light 1 m over a 2 m x 2 m floor against the exact Omega_j/(4 pi A_j); relative errors "
                 "|r - exact|/exact per patch, binned by patch width in pixels [lo, hi)\n");
    std::fprintf(out, "backend,estimator,resolution,patch_size_m,width_px_lo,width_px_hi,patches,max_rel_error,rms_rel_error,"
                      "mean_abs_rel_error,preprocess_seconds\n");
    for (const std::string& backend : backends)
      for (const std::string& estimator : estimators)
        for (int R : resolutions)
          for (double patchSize : patchSizes) {
            PreprocessOptions o = defaultOptions(scene);
            o.settings.resolution = uint32_t(R), o.settings.backend = backend, o.settings.estimator = estimator;
            o.settings.patchSize = patchSize, o.threads = threads, o.quiet = true;
            const auto t0 = std::chrono::steady_clock::now();
            const FirstShotTable t = preprocessScene(scene, o);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::map<int, Bin> bins;
            for (uint32_t j = 0; j < t.mesh.size(); ++j) {
              const Patch& p = t.mesh.patches[j];
              const std::vector<Vec3d> poly(p.v, p.v + p.count);
              const double exact = analytic::solidAnglePolygon(eye, poly) / (4 * kPi * p.area);
              double r = 0;
              for (uint64_t k = t.rowStart[j]; k < t.rowStart[j + 1]; ++k) r += t.factor[k];
              const double rel = std::abs(r - exact) / exact;
              Bin& b = bins[int(std::floor(std::log2(widthInPixels(p, eye, R))))];
              b.sumSq += rel * rel, b.sumAbs += rel, b.max = std::max(b.max, rel), ++b.n;
            }
            for (const auto& [k, b] : bins)
              std::fprintf(out, "%s,%s,%d,%g,%g,%g,%d,%.6g,%.6g,%.6g,%.4f\n", backend.c_str(), estimator.c_str(), R,
                           patchSize, std::ldexp(1.0, k), std::ldexp(1.0, k + 1), b.n, b.max, std::sqrt(b.sumSq / b.n),
                           b.sumAbs / b.n, seconds);
            std::fflush(out);
          }
    if (out != stdout) std::fclose(out);
    return 0;
  });
}
