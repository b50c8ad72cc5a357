#pragma once
/// @file cli.h
/// The path tracer's command line (render/integrators/integrator_cli.h): no options of its own; it reads every
/// shared one but --shoot-firstshot.
#include "render/integrators/integrator_cli.h"
#include "render/integrators/path/integrator.h"

namespace firstshot {

struct PathCli : SharedOptionsCli<PathIntegrator> {
  PathCli()
      : SharedOptionsCli({integrator_option::kPrimary, integrator_option::kLightSampler, integrator_option::kPatchNee,
                          integrator_option::kLightVisibility, integrator_option::kTableVisibility,
                          integrator_option::kLuminaires}) {}
};

}  // namespace firstshot
