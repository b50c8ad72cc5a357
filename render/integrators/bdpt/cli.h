#pragma once
/// @file cli.h
/// BDPT's command line (render/integrators/integrator_cli.h): no options of its own. It reads the light
/// sampler's options (its small lights' NEE in table mode), --table-visibility, --shoot-firstshot,
/// --luminaires and --emitter-choice; not --primary or --patch-nee (the small lights are taken exactly at the first
/// non-delta camera vertex, docs/bdpt.md).
#include "render/integrators/integrator_cli.h"
#include "render/integrators/bdpt/integrator.h"

namespace firstshot {

struct BdptCli : SharedOptionsCli<BdptIntegrator> {
  BdptCli()
      : SharedOptionsCli({integrator_option::kLightSampler, integrator_option::kLightVisibility,
                          integrator_option::kTableVisibility, integrator_option::kShootFirstShot,
                          integrator_option::kLuminaires, integrator_option::kEmitterChoice}) {}
};

}  // namespace firstshot
