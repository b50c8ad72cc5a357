#pragma once
/// @file cli.h
/// BDPT's command line (render/integrators/integrator_cli.h): no options of its own. It reads the light
/// sampler's options (its small lights' NEE in table mode), --table-visibility and
/// --shoot-firstshot; not --primary or --patch-nee (the small lights are taken exactly at the first
/// non-delta camera vertex, docs/bdpt.md).
#include <memory>
#include <string>
#include <vector>

#include "render/integrators/integrator_cli.h"
#include "render/integrators/bdpt/integrator.h"

namespace fs {

class BdptCli : public IntegratorCli {
 public:
  std::unique_ptr<Integrator> make(const IntegratorOptions& options) const override {
    return std::make_unique<BdptIntegrator>(options);
  }

 protected:
  std::vector<std::string> shared() const override {
    using namespace integrator_option;
    return {kLightSampler, kLightVisibility, kTableVisibility, kShootFirstShot};
  }
};

}  // namespace fs
