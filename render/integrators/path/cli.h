#pragma once
/// @file cli.h
/// The path tracer's command line (render/integrators/integrator_cli.h): no options of its own; it reads every
/// shared one but --shoot-firstshot.
#include <memory>
#include <string>
#include <vector>

#include "render/integrators/integrator_cli.h"
#include "render/integrators/path/integrator.h"

namespace fs {

class PathCli : public IntegratorCli {
 public:
  std::unique_ptr<Integrator> make(const IntegratorOptions& options) const override {
    return std::make_unique<PathIntegrator>(options);
  }

 protected:
  std::vector<std::string> shared() const override {
    using namespace integrator_option;
    return {kPrimary, kLightSampler, kPatchNee, kLightVisibility, kTableVisibility};
  }
};

}  // namespace fs
