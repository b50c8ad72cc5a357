#pragma once
/// @file cli.h
/// Light tracing's command line (render/integrators/integrator_cli.h): --light-paths. It reads every shared
/// option: --shoot-firstshot, --luminaires (particles from the exit patches), and the others through the small lights'
/// NEE (table mode) and the path tracer it hands the pixels whose first hit is a mirror or glass
/// (docs/light-tracing.md).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <memory>
#include <string>
#include <vector>

#include "common/util/memory_limit.h"
#include "render/integrators/integrator_cli.h"
#include "render/integrators/light/integrator.h"

namespace firstshot {

class LightCli : public IntegratorCli {
 public:
  void add(CLI::App& app) override {
    app.add_option("--light-paths", lightPaths_, "light: light paths per pixel in each pass (0: automatic, 8 and at most "
                                                 "2^21 per pass, or 1 in scenes with mirrors or glass; "
                                                 "docs/light-tracing.md)")
        ->check(CLI::Range(0, 4096))->capture_default_str();
    own_ = {"--light-paths"};
  }

  /// @throws InputError (--light-paths) when the splats of a pass would not fit in memory.
  void configure(IntegratorSetup& setup) override {
    if (lightPaths_ > 0)
      requireMemory(double(lightPaths_) * setup.scene->camera.width * setup.scene->camera.height *
                        LightTracingIntegrator::kSplatBytesPerPath, "",
                    "--light-paths", fmt::format("the splats of {} light paths per pixel", lightPaths_),
                    "lower --light-paths");
  }

  std::unique_ptr<Integrator> make(const IntegratorOptions& options) const override {
    IntegratorOptions o = options;
    if (lightPaths_ > 0) o.lightPathsPerPixel = lightPaths_;
    return std::make_unique<LightTracingIntegrator>(o);
  }

 protected:
  std::vector<std::string> shared() const override {
    using namespace integrator_option;
    return {kPrimary,         kLightSampler, kPatchNee,     kLightVisibility,
            kTableVisibility, kShootFirstShot, kLuminaires, kEmitterChoice};
  }

 private:
  int lightPaths_ = 0;  ///< IntegratorOptions::lightPathsPerPixel
};

}  // namespace firstshot
