// firstshot-variance: where a path-traced image's variance comes from, by path length and by what brought the
// light (bench/variance_report.h). Renders the scene's view with the path tracer (the `path` integrator, with or
// without a first-shot table and patch NEE) and prints the categories' shares of the image's mean and variance.
//
// Usage: firstshot-variance SCENE [--firstshot F.fsd] [--patch-nee off|first|every] [--spp N] [--width W
//        --height H] [--seed S] [--threads T] [--max-depth D] [--light-sampler tree|all] [--sampler
//        independent|sobol] [--top K] [--csv OUT.csv]
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>
#include <string>

#include "bench/variance_report.h"
#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "render/integrators/integrator.h"

using namespace firstshot;

int main(int argc, char** argv) {
  CLI::App app("firstshot-variance: an image's mean and variance split by path length and by what brought the light "
               "(the path tracer)");
  std::string scenePath, fsdPath, patchNee = "off", lightSampler = "tree", samplerName = "independent", csvPath;
  int spp = 32, width = 0, height = 0, threads = 0, maxDepth = -1, top = 15;
  std::optional<uint64_t> seed;
  app.add_option("scene", scenePath, "scene file (JSON, Mitsuba XML, an asset)")->required();
  app.add_option("--firstshot", fsdPath, "first-shot table (.fsd) of the scene");
  app.add_option("--patch-nee", patchNee, "with --firstshot: sample the lit patches as emitters")
      ->check(CLI::IsMember({"off", "first", "every"}));
  app.add_option("--light-sampler", lightSampler, "NEE's choice of lights")->check(CLI::IsMember({"tree", "all"}));
  // Independent samples by default (firstshot-render's default is sobol): a pixel's samples are then independent, so
  // their sample variance over spp is the variance of its estimate, and shares of it add up as the report says.
  app.add_option("--sampler", samplerName, "samples' numbers (default independent, unlike firstshot-render: the "
                                           "variances are then those of the pixel estimates)")
      ->check(CLI::IsMember({"independent", "sobol"}));
  app.add_option("--spp", spp, "samples per pixel (at least 2)")->check(CLI::Range(2, 1 << 20));
  app.add_option("--width", width, "image width (default: the scene's camera)")->check(CLI::Range(1, 1 << 14));
  app.add_option("--height", height, "image height (default: the scene's camera)")->check(CLI::Range(1, 1 << 14));
  app.add_option("--seed", seed, "random seed (default: the scene's settings.seed)");
  app.add_option("--threads", threads, "worker threads (0: all); the report does not depend on it");
  app.add_option("--max-depth", maxDepth, "longest path in bounces (default: the scene's settings.max_depth)");
  app.add_option("--top", top, "categories printed in the first table")->check(CLI::Range(0, 1000));
  app.add_option("--csv", csvPath, "also write every category as CSV here");
  CLI11_PARSE(app, argc, argv);

  try {
    SceneDesc desc = loadScene(scenePath);
    if (width > 0) desc.camera.width = width;
    if (height > 0) desc.camera.height = height;
    IntegratorOptions io;
    io.maxDepth = maxDepth >= 0 ? maxDepth : desc.settings.maxDepth;
    io.patchNee = patchNee == "off" ? PatchNee::Off : patchNee == "first" ? PatchNee::First : PatchNee::Every;
    io.lightSampler = lightSampler == "all" ? LightStrategy::All : LightStrategy::Tree;
    VarianceReportOptions o;
    o.spp = spp;
    o.seed = seed ? *seed : desc.settings.seed;
    o.threads = threads;
    o.sampler = samplerName == "sobol" ? SamplerMode::Sobol : SamplerMode::Independent;
    // As firstshot-render: the table's patches with a table, else every face as it is (the path tracer needs none).
    const RenderScene scene = fsdPath.empty()
                                  ? RenderScene(desc)
                                  : RenderScene(desc, readFirstShot(fsdPath, hashScene(desc)), fsdPath);
    if (fsdPath.empty() && io.patchNee != PatchNee::Off)
      fmt::print(stderr, "firstshot-variance: --patch-nee needs --firstshot; it does nothing here\n");
    auto path = makeIntegrator("path", io);
    path->preprocess(scene);
    const VarianceReport report = varianceReport(*path, scene, o);
    fmt::print("{} ({}, patch NEE {}, max depth {}, seed {}):\n{}", scenePath,
               fsdPath.empty() ? "no table" : "table " + fsdPath, patchNee, io.maxDepth, o.seed,
               formatVarianceReport(report, top));
    if (!csvPath.empty()) {
      std::ofstream csv(csvPath);
      csv << varianceReportCsv(report);
      if (!csv) throw std::runtime_error("cannot write " + csvPath);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "firstshot-variance: {}\n", e.what());
    return 1;
  }
  return 0;
}
