#pragma once
/// @file cli.h
/// The ray-bundle integrator's command line (render/integrators/integrator_cli.h; header-only, included by the
/// table in render/integrators/integrator.cpp): its options and the integrator made with them. Of the shared
/// options it reads --primary and --table-visibility (NEE at camera-visible points, docs/bundle.md).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <string>
#include <vector>

#include "common/util/error.h"
#include "render/integrators/bundle/integrator.h"
#include "render/integrators/integrator_cli.h"

namespace firstshot {

class BundleCli : public IntegratorCli {
 public:
  /// Largest accepted B (B² lines per bundle).
  static constexpr int kMaxResolution = 16384;
  BundleSettings settings;
  int iterations = 0;
  std::string directions;  ///< empty: halton with --sampler sobol (the default), random with --sampler independent
  CLI::Option* iterationsOption = nullptr;
  bool configured = false;  ///< configure() ran: make() hands the settings to the integrator

  void add(CLI::App& app) override {
    const std::vector<CLI::Option*> declared = {
        iterationsOption = app.add_option("--iterations", iterations, "bundle: iterations (one global transfer and one "
                                                                      "image estimate each; the same as --spp)"),
        app.add_option("--bundle-resolution", settings.resolution, "bundle: B, the grid of B×B parallel lines per "
                                                                   "iteration over the scene's bounding disk")
            ->capture_default_str(),
        app.add_option("--bundle-directions", directions, "bundle: global directions: random (uniform, independent) "
                                                          "or halton (low-discrepancy, rotated per seed); default: "
                                                          "halton with --sampler sobol, random with independent"),
    };
    for (const CLI::Option* o : declared) own_.push_back(o->get_name());
  }

  /// Checks the values, keeps the settings for make() and turns --iterations into the setup's spp.
  /// @throws InputError for a bad value, or for --iterations with --spp or --time.
  void configure(IntegratorSetup& setup) override {
    if (iterationsOption->count() > 0) {
      if (setup.app->count("--spp") || setup.app->count("--time"))
        throw InputError("", "--iterations", "give one of --iterations, --spp and --time");
      if (iterations < 1) throw InputError("", "--iterations", fmt::format("must be at least 1, got {}", iterations));
      setup.spp = iterations;
    }
    if (settings.resolution < 1 || settings.resolution > kMaxResolution)
      throw InputError("", "--bundle-resolution",
                       fmt::format("must be between 1 and {} lines per side of the grid, got {}", kMaxResolution,
                                   settings.resolution));
    if (directions.empty()) directions = setup.sampler == SamplerMode::Sobol ? "halton" : "random";
    if (directions == "random") {
      settings.directions = BundleDirections::Random;
    } else if (directions == "halton") {
      settings.directions = BundleDirections::Halton;
    } else {
      throw InputError("", "--bundle-directions", "expected random or halton, got \"" + directions + "\"");
    }
    configured = true;
  }

  std::unique_ptr<Integrator> make(const IntegratorOptions& options) const override {
    auto bundle = std::make_unique<BundleIntegrator>(options);
    if (configured) bundle->setSettings(settings);
    return bundle;
  }

  bool needsPatches() const override { return true; }

 protected:
  std::vector<std::string> shared() const override {
    using namespace integrator_option;
    return {kPrimary, kTableVisibility};
  }
};

}  // namespace firstshot
