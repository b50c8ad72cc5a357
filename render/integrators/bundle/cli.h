#pragma once
/// @file cli.h
/// The command-line options of the ray-bundle integrator for firstshot-render (header-only,
/// included by render/main.cpp, which links CLI11): declaring them and handing them to the
/// integrator before preprocess().
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <string>
#include <vector>

#include "common/error.h"
#include "render/integrators/bundle/integrator.h"

namespace fs {

struct BundleCli {
  /// Largest accepted B (B² lines per bundle).
  static constexpr int kMaxResolution = 16384;
  BundleSettings settings;
  int iterations = 0;
  std::string directions = "random";
  std::vector<CLI::Option*> options;
  CLI::Option* iterationsOption = nullptr;

  void add(CLI::App& app) {
    options = {
        iterationsOption = app.add_option("--iterations", iterations, "bundle: iterations (one global transfer and one "
                                                                      "image estimate each; the same as --spp)"),
        app.add_option("--bundle-resolution", settings.resolution, "bundle: B, the grid of B×B parallel lines per "
                                                                   "iteration over the scene's bounding disk")
            ->capture_default_str(),
        app.add_option("--bundle-directions", directions, "bundle: global directions: random (uniform, independent) "
                                                          "or halton (low-discrepancy, rotated per seed)")
            ->capture_default_str(),
    };
  }

  /// Hands the settings to @p integrator if it is the bundle integrator and turns --iterations into
  /// @p spp. @throws InputError for a bad value, for --iterations with --spp or --time, or for any
  /// of these options given with another integrator.
  void configure(Integrator& integrator, int& spp, const CLI::App& app) {
    auto* bundle = dynamic_cast<BundleIntegrator*>(&integrator);
    if (!bundle) {
      for (const CLI::Option* o : options)
        if (o->count() > 0) throw InputError("", o->get_name(), "only with --integrator bundle");
      return;
    }
    if (iterationsOption->count() > 0) {
      if (app.count("--spp") || app.count("--time"))
        throw InputError("", "--iterations", "give one of --iterations, --spp and --time");
      if (iterations < 1) throw InputError("", "--iterations", fmt::format("must be at least 1, got {}", iterations));
      spp = iterations;
    }
    if (settings.resolution < 1 || settings.resolution > kMaxResolution)
      throw InputError("", "--bundle-resolution",
                       fmt::format("must be between 1 and {} lines per side of the grid, got {}", kMaxResolution,
                                   settings.resolution));
    if (directions == "random") {
      settings.directions = BundleDirections::Random;
    } else if (directions == "halton" || directions == "sobol") {
      settings.directions = BundleDirections::Halton;
    } else {
      throw InputError("", "--bundle-directions", "expected random or halton, got \"" + directions + "\"");
    }
    bundle->setSettings(settings);
  }
};

}  // namespace fs
